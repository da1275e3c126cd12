#include "hapi_surface/mesh_extraction.hpp"

#include "hapi_surface/marching_tetrahedra.hpp"

#include <unordered_map>

namespace hapi_surface {
namespace {

class Extractor {
 public:
  explicit Extractor(const TsdfVolume& v)
      : vol_(v),
        g_(v.grid()),
        tsdf_(v.tsdf()),
        w_(v.weight()),
        min_w_(static_cast<float>(v.settings().mesh_min_weight)),
        offsets_(cubeOffsets(static_cast<unsigned int>(v.grid().dims.x()), static_cast<unsigned int>(v.grid().dims.y()))) {}

  Mesh run() {
    const Eigen::Vector3i& d = g_.dims;
    reserveVertexIds();
    for (int k = 0; k + 1 < d.z(); ++k)
      for (int j = 0; j + 1 < d.y(); ++j) {
        const auto row = static_cast<std::uint32_t>(g_.index(0, j, k));
        for (int i = 0; i + 1 < d.x(); ++i) {
          const std::uint32_t g = row + static_cast<std::uint32_t>(i);
          cell(g);
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
    TetTriangles tt;
    for (int t = 0; t < 6; ++t) {
      const int n = tetrahedronTriangles(t, f, &tt);
      for (int k = 0; k < n; ++k) {
        std::int32_t v[3];
        for (int e = 0; e < 3; ++e) {
          const int a = tt.edge[k][e][0], b = tt.edge[k][e][1];
          v[e] = vertex(idx[a], idx[b], f[a], f[b]);
        }
        triangle(v[0], v[1], v[2]);
      }
    }
  }

  // Counter-clockwise seen from outside (the side the normals point to).
  void triangle(std::int32_t a, std::int32_t b, std::int32_t c) {
    const auto& V = mesh_.vertices;
    const auto& N = mesh_.normals;
    if (!windingAgreesWithNormals(V[a].data(), V[b].data(), V[c].data(), N[a].data(), N[b].data(), N[c].data()))
      std::swap(b, c);
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
    const Eigen::Vector3f pa = position(ga), pb = position(gb), na = vol_.gradient(ga), nb = vol_.gradient(gb);
    Eigen::Vector3f p, n;
    float t = 0;
    edgeVertex(pa.data(), pb.data(), fa, fb, na.data(), nb.data(), p.data(), n.data(), &t);
    const auto id = static_cast<std::int32_t>(mesh_.vertices.size());
    mesh_.vertices.push_back(p);
    mesh_.normals.push_back(n);
    mesh_.vertex_edges.push_back({ga, gb});
    mesh_.vertex_t.push_back(t);
    ids_.emplace(key, id);
    return id;
  }

  Eigen::Vector3f position(std::uint32_t g) const {
    const Eigen::Vector3i c = g_.coords(g);
    Eigen::Vector3f p;
    gridPointPosition(g_.origin.data(), g_.voxel, c.x(), c.y(), c.z(), p.data());
    return p;
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

Mesh extractMesh(const TsdfVolume& volume) { return Extractor(volume).run(); }

}  // namespace hapi_surface
