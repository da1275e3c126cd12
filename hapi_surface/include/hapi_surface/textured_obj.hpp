// The surface as a Wavefront OBJ with its projected values as a texture:
// NAME.obj (vertices, normals, texture coordinates, triangles), NAME.mtl
// (one material whose diffuse map is the texture) and NAME.png (the atlas),
// for viewers that show textures (MeshLab, Open3D, Blender).
//
// The atlas gives each triangle its own square cell of `cell` x `cell`
// texels: the triangle's corners lie on the centres of the cell's texels
// (0, 0), (cell-1, 0) and (0, cell-1), so each corner texel holds exactly
// its vertex's colour; the other texels interpolate the three colours
// linearly (barycentric, clamped to the triangle beyond its long edge, so
// filtering at the edge does not pick up a neighbouring cell's colours).
#pragma once

#include "hapi_surface/colour_map.hpp"
#include "hapi_surface/mesh.hpp"
#include "hapi_surface/surface_status.hpp"

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace hapi_surface {

struct TextureAtlas {
  int width = 0, height = 0;
  std::vector<Rgb8> texels;                         // row-major, top row first
  std::vector<std::array<Eigen::Vector2f, 3>> uv;   // per face, OBJ convention: v = 0 at the bottom row
};

// Cells of `cell` >= 2 texels; colours: one per vertex.
TextureAtlas buildTextureAtlas(const Mesh& mesh, const std::vector<Rgb8>& colours, int cell = 4);

// Writes `obj_path` (ending in .obj) and the .mtl and .png of the same name
// next to it. kIoError when a file cannot be written, kSizeMismatch when the
// colours are not one per vertex, kNoVolume for an empty mesh.
SurfaceStatus writeTexturedObj(const std::string& obj_path, const Mesh& mesh, const std::vector<Rgb8>& colours,
                               int cell = 4);

// Whether `path` names an OBJ file (ends in .obj, any case).
bool isObjPath(const std::string& path);

}  // namespace hapi_surface
