// Between the filter's pool and a map file's landmarks (docs/DESIGN.md "Map
// file"): the pool as saved (LandmarkInfo with marginal covariances, the
// descriptors in the same order) and a loaded map as prior landmarks
// (Eskf::loadMap).
#pragma once

#include "hapi_eskf/map_file/map_data.hpp"

#include <cstdint>
#include <vector>

namespace hapi_eskf {
namespace map_file {

// The pool's landmarks whose values a map file can hold (map_checks.hpp:
// a landmark the reader would refuse, e.g. a marginal that lost positive
// definiteness numerically, is left out and counted in `skipped`).
std::vector<MapLandmark> toMapLandmarks(const std::vector<LandmarkInfo>& pool, const std::vector<uint8_t>& descriptors,
                                        uint32_t descriptor_length, int* skipped);
std::vector<PriorLandmark> toPriorLandmarks(const MapData& map);

}  // namespace map_file
}  // namespace hapi_eskf
