// PLY files of a surface (binary little endian): vertices with normals,
// colour, the projected value and its weight, faces as vertex index lists.
// The reader takes any PLY of one vertex and one face element whose
// properties are scalar (float, double, char/uchar, short/ushort, int/uint in
// any of the names PLY uses) with x, y, z (others optional, missing values:
// NaN); it checks every count against the file's size, so a hostile header
// cannot make it allocate more than the file holds.
#pragma once

#include "hapi_surface/colour_map.hpp"
#include "hapi_surface/mesh.hpp"
#include "hapi_surface/surface_status.hpp"

#include <string>
#include <vector>

namespace hapi_surface {

// colours: one per vertex, or empty (then the jet colour of the values).
SurfaceStatus writePly(const std::string& path, const Mesh& mesh, const std::vector<Rgb8>& colours);
// The bytes of the same file.
std::string plyBytes(const Mesh& mesh, const std::vector<Rgb8>& colours);

// *mesh (vertices, normals if present, faces, values if present) and
// *colours (empty if the file has none); kParseError with *why on any
// inconsistency, and then both are untouched.
SurfaceStatus parsePly(const std::string& bytes, Mesh* mesh, std::vector<Rgb8>* colours, std::string* why);
SurfaceStatus readPly(const std::string& path, Mesh* mesh, std::vector<Rgb8>* colours, std::string* why);

}  // namespace hapi_surface
