#include "hapi_surface/surface_values.hpp"

#include "hapi_surface/mesh_depth_render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapi_surface {
namespace {

// Bilinear sample at (u, v) (pixel centres at integers); NaN when outside or
// when one of the four pixels has no value.
float bilinear(const FloatImage& im, double u, double v) {
  if (!(u >= 0 && v >= 0 && u <= im.width - 1 && v <= im.height - 1)) return std::numeric_limits<float>::quiet_NaN();
  const int u0 = std::min(static_cast<int>(u), im.width - 2 < 0 ? 0 : im.width - 2);
  const int v0 = std::min(static_cast<int>(v), im.height - 2 < 0 ? 0 : im.height - 2);
  const int u1 = std::min(u0 + 1, im.width - 1), v1 = std::min(v0 + 1, im.height - 1);
  const double a = u - u0, b = v - v0;
  const double s = (1 - a) * (1 - b) * im.at(u0, v0) + a * (1 - b) * im.at(u1, v0) + (1 - a) * b * im.at(u0, v1) +
                   a * b * im.at(u1, v1);
  return std::isfinite(s) ? static_cast<float>(s) : std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

SurfaceValues::SurfaceValues(std::size_t voxels) : sum_w_(voxels, 0.f), sum_wv_(voxels, 0.f) {}

void SurfaceValues::clear() {
  std::fill(sum_w_.begin(), sum_w_.end(), 0.f);
  std::fill(sum_wv_.begin(), sum_wv_.end(), 0.f);
}

ProjectionResult SurfaceValues::addFrame(const TsdfVolume& volume, const Mesh& mesh, const FloatImage& image,
                                         const PinholeCamera& cam, const Eigen::Isometry3d& T_world_camera) {
  ProjectionResult r;
  if (cam.check() != SurfaceStatus::kOk) r.status = SurfaceStatus::kBadCamera;
  else if (checkPose(T_world_camera) != SurfaceStatus::kOk) r.status = SurfaceStatus::kBadPose;
  else if (image.width != cam.width || image.height != cam.height ||
           image.data.size() != static_cast<std::size_t>(cam.width) * cam.height ||
           volume.grid().size() != sum_w_.size())
    r.status = SurfaceStatus::kSizeMismatch;
  else if (mesh.empty())
    r.status = SurfaceStatus::kNoVolume;
  if (r.status != SurfaceStatus::kOk) return r;

  const SurfaceSettings& s = volume.settings();
  const VoxelGrid& g = volume.grid();
  const FloatImage zbuf = renderMeshDepth(mesh, cam, T_world_camera);
  const Eigen::Isometry3d T_cw = T_world_camera.inverse();
  const Eigen::Vector3d centre = T_world_camera.translation();
  // The voxels at the ends of the mesh's vertex edges carry the values
  // (S5): those the vertices are sampled from.
  std::vector<std::uint32_t> voxels;
  voxels.reserve(2 * mesh.vertex_edges.size());
  for (const auto& e : mesh.vertex_edges)
    for (std::uint32_t v : e)
      if (v < sum_w_.size()) voxels.push_back(v);
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  for (const std::uint32_t idx : voxels) {
    const Eigen::Vector3i c = g.coords(idx);
    const Eigen::Vector3d x = g.centre(c.x(), c.y(), c.z());
    const Eigen::Vector3d p = T_cw * x;
    if (!cam.nearView(p)) continue;
    const Eigen::Vector2d uv = cam.project(p);
    const double u = uv.x(), v = uv.y();
    const int pu = static_cast<int>(std::floor(u + 0.5)), pv = static_cast<int>(std::floor(v + 0.5));
    if (pu < 0 || pv < 0 || pu >= cam.width || pv >= cam.height) continue;
    // Occlusion (S4): the rendered surface must not lie in front.
    if (!(p.z() <= zbuf.at(pu, pv) + s.occlusion_tolerance)) {
      ++r.voxels_occluded;
      continue;
    }
    const Eigen::Vector3f n = volume.gradient(idx).normalized();
    const double cos_view = -n.cast<double>().dot((x - centre).normalized());
    if (!(cos_view >= s.min_view_cos)) continue;
    const float value = bilinear(image, u, v);
    if (!std::isfinite(value)) continue;
    const double ratio = s.reference_distance / p.z();
    const auto wt = static_cast<float>(cos_view * ratio * ratio);
    sum_w_[idx] += wt;
    sum_wv_[idx] += wt * value;
    ++r.voxels_updated;
  }
  return r;
}

void SurfaceValues::sampleVertices(Mesh* mesh) const {
  const std::size_t n = mesh->vertices.size();
  mesh->values.assign(n, std::numeric_limits<float>::quiet_NaN());
  mesh->value_weights.assign(n, 0.f);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& e = mesh->vertex_edges[i];
    if (e[0] >= sum_w_.size() || e[1] >= sum_w_.size()) continue;
    const float t = mesh->vertex_t[i];
    const float ends[2] = {1.f - t, t};
    double num = 0, den = 0, wsum = 0;
    for (int k = 0; k < 2; ++k) {
      const float sw = sum_w_[e[k]];
      if (!(sw > 0.f)) continue;
      num += ends[k] * (sum_wv_[e[k]] / sw);
      den += ends[k];
      wsum += ends[k] * sw;
    }
    if (den <= 0) continue;
    mesh->values[i] = static_cast<float>(num / den);
    mesh->value_weights[i] = static_cast<float>(wsum);
  }
}

}  // namespace hapi_surface
