#include "hapi_surface/mesh_extraction.hpp"

#include <unordered_map>

namespace hapi_surface {
namespace {

// The Kuhn split of a cube (corners as cubeOffsets(), tsdf_math.hpp): 6
// tetrahedra sharing the diagonal 0-6. The same split in every cube cuts each
// shared face along the same diagonal from both sides, so neighbouring
// tetrahedra meet exactly.
constexpr int kTet[6][4] = {{0, 5, 1, 6}, {0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}};

class Extractor {
 public:
  explicit Extractor(const TsdfVolume& v)
      : vol_(v),
        g_(v.grid()),
        tsdf_(v.tsdf()),
        w_(v.weight()),
        min_w_(static_cast<float>(v.settings().mesh_min_weight)),
        offsets_(cubeOffsets(static_cast<unsigned int>(v.grid().dims.x()), static_cast<unsigned int>(v.grid().dims.y()))) {}

  // active: nullptr, or one byte per voxel, 0 where the cube of that corner
  // 0 is known not to be meshed (the others are tested here as well).
  Mesh run(const std::vector<std::uint8_t>* active) {
    const Eigen::Vector3i& d = g_.dims;
    reserveVertexIds();
    for (int k = 0; k + 1 < d.z(); ++k)
      for (int j = 0; j + 1 < d.y(); ++j) {
        const auto row = static_cast<std::uint32_t>(g_.index(0, j, k));
        for (int i = 0; i + 1 < d.x(); ++i) {
          const std::uint32_t g = row + static_cast<std::uint32_t>(i);
          if (!active || (*active)[g]) cell(g);
        }
      }
    return std::move(mesh_);
  }

 private:
  // About one vertex per surface voxel: the surface of a scan is a sheet
  // across the volume.
  void reserveVertexIds() { ids_.reserve(static_cast<std::size_t>(2 * g_.dims.x()) * g_.dims.y()); }

  // The cube whose corner 0 is grid point g.
  void cell(std::uint32_t g) {
    if (!cubeActive(tsdf_.data(), w_.data(), g, offsets_, min_w_)) return;
    std::uint32_t idx[8];
    float f[8];
    for (int c = 0; c < 8; ++c) {
      idx[c] = g + offsets_.o[c];
      f[c] = tsdf_[idx[c]];
    }
    for (const auto& t : kTet) tetrahedron(idx, f, t);
  }

  void tetrahedron(const std::uint32_t* idx, const float* f, const int* t) {
    int in[4], out[4], n_in = 0, n_out = 0;
    for (int c = 0; c < 4; ++c) (f[t[c]] < 0.f ? in[n_in++] : out[n_out++]) = t[c];
    if (n_in == 0 || n_out == 0) return;
    if (n_in == 1 || n_out == 1) {
      const bool lone_in = n_in == 1;
      const int lone = lone_in ? in[0] : out[0];
      const int* others = lone_in ? out : in;
      triangle(vertex(idx[lone], idx[others[0]], f[lone], f[others[0]]),
               vertex(idx[lone], idx[others[1]], f[lone], f[others[1]]),
               vertex(idx[lone], idx[others[2]], f[lone], f[others[2]]));
      return;
    }
    // Two in, two out: a quad whose corners go round the tetrahedron.
    const std::int32_t a = vertex(idx[in[0]], idx[out[0]], f[in[0]], f[out[0]]);
    const std::int32_t b = vertex(idx[in[0]], idx[out[1]], f[in[0]], f[out[1]]);
    const std::int32_t c = vertex(idx[in[1]], idx[out[1]], f[in[1]], f[out[1]]);
    const std::int32_t d = vertex(idx[in[1]], idx[out[0]], f[in[1]], f[out[0]]);
    triangle(a, b, c);
    triangle(a, c, d);
  }

  // Counter-clockwise seen from outside (the side the normals point to).
  void triangle(std::int32_t a, std::int32_t b, std::int32_t c) {
    const auto& V = mesh_.vertices;
    const Eigen::Vector3f n = (V[b] - V[a]).cross(V[c] - V[a]);
    const Eigen::Vector3f out = mesh_.normals[a] + mesh_.normals[b] + mesh_.normals[c];
    if (n.dot(out) < 0.f) std::swap(b, c);
    mesh_.faces.push_back({a, b, c});
  }

  // The shared vertex on the edge between grid points ga and gb.
  std::int32_t vertex(std::uint32_t ga, std::uint32_t gb, float fa, float fb) {
    if (ga > gb) {
      std::swap(ga, gb);
      std::swap(fa, fb);
    }
    const std::uint64_t key = static_cast<std::uint64_t>(ga) * g_.size() + gb;
    const auto it = ids_.find(key);
    if (it != ids_.end()) return it->second;
    const float t = fa / (fa - fb);
    const Eigen::Vector3f pa = position(ga), pb = position(gb);
    Eigen::Vector3f n = (1.f - t) * vol_.gradient(ga) + t * vol_.gradient(gb);
    const float len = n.norm();
    n = len > 0.f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::UnitZ();
    const auto id = static_cast<std::int32_t>(mesh_.vertices.size());
    mesh_.vertices.push_back(pa + t * (pb - pa));
    mesh_.normals.push_back(n);
    mesh_.vertex_edges.push_back({ga, gb});
    mesh_.vertex_t.push_back(t);
    ids_.emplace(key, id);
    return id;
  }

  Eigen::Vector3f position(std::uint32_t g) const {
    const Eigen::Vector3i c = g_.coords(g);
    return g_.centre(c.x(), c.y(), c.z()).cast<float>();
  }

  const TsdfVolume& vol_;
  const VoxelGrid& g_;
  const std::vector<float>& tsdf_;
  const std::vector<float>& w_;
  float min_w_;
  Mesh mesh_;
  std::unordered_map<std::uint64_t, std::int32_t> ids_;
  const CubeOffsets offsets_;
};

}  // namespace

Mesh extractMesh(const TsdfVolume& volume, const std::vector<std::uint8_t>* active_cells) {
  const bool usable = active_cells && active_cells->size() == volume.grid().size();
  return Extractor(volume).run(usable ? active_cells : nullptr);
}

}  // namespace hapi_surface
