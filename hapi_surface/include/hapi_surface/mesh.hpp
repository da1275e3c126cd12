// A triangle mesh with shared vertices, per-vertex normals and the projected
// imaging value of each vertex (NaN: never seen).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace hapi_surface {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;  // unit, pointing out of the skin (towards free space)
  std::vector<std::array<std::int32_t, 3>> faces;
  std::vector<float> values;  // projected imaging value per vertex, NaN = none; empty = not projected
  std::vector<float> value_weights;  // total weight behind each value (0 = none)

  // The volume edge each vertex lies on (grid indices of its ends, and the
  // fraction t from the first): values are looked up there.
  std::vector<std::array<std::uint32_t, 2>> vertex_edges;
  std::vector<float> vertex_t;

  bool empty() const { return faces.empty(); }
};

}  // namespace hapi_surface
