// Writes a map file (docs/DESIGN.md "Map file"). The map is checked first
// (map_checks.hpp): a map the reader would refuse is never written.
#pragma once

#include "hapi_eskf/map_file/map_data.hpp"
#include "hapi_eskf/map_file/map_error.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace map_file {

// The file's bytes; on a fault `error` is set and the result is empty.
std::vector<uint8_t> encodeMap(const MapData& map, MapError* error);
// Writes "<path>.tmp" and renames it, so no reader ever sees half a file.
MapError writeMapFile(const std::string& path, const MapData& map);

}  // namespace map_file
}  // namespace hapi_eskf
