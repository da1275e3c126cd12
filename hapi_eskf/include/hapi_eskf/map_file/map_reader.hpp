// Reads and checks a map file (docs/DESIGN.md "Map file"): the layout
// (magic, version, section table, sizes), every value (map_checks.hpp) and,
// when given, the running front end's descriptor type and calibration. The
// output is assigned only when everything passed: nothing loads half.
#pragma once

#include "hapi_eskf/map_file/map_data.hpp"
#include "hapi_eskf/map_file/map_error.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace hapi_eskf {
namespace map_file {

// What the running system is; an unset field is not compared.
struct MapExpectation {
  int descriptor_type = -1;                     // -1: any known type
  const MapCalibration* calibration = nullptr;  // nullptr: not compared
};

MapError decodeMap(const uint8_t* data, std::size_t size, const MapExpectation& expect, MapData* out);
MapError readMapFile(const std::string& path, const MapExpectation& expect, MapData* out);

}  // namespace map_file
}  // namespace hapi_eskf
