#include "hapi_surface/tsdf_volume.hpp"

#include "hapi_surface/marching_tetrahedra.hpp"

#include <cmath>

namespace hapi_surface {

VoxelGrid VoxelGrid::centredAt(const Eigen::Vector3d& centre, const SurfaceSettings& s) {
  VoxelGrid g;
  g.voxel = s.voxel_size;
  const Eigen::Vector3d size(s.volume_size_x, s.volume_size_y, s.volume_size_z);
  for (int a = 0; a < 3; ++a) g.dims[a] = static_cast<int>(std::ceil(size[a] / s.voxel_size));
  g.origin = centre - 0.5 * s.voxel_size * g.dims.cast<double>();
  return g;
}

SurfaceStatus checkDepthFrame(const DepthFrame& f, const SurfaceSettings& s) {
  // Depth images are rectified: the integration (S1) projects without distortion.
  if (f.camera.check() != SurfaceStatus::kOk || f.camera.hasDistortion()) return SurfaceStatus::kBadCamera;
  if (checkPose(f.T_world_camera) != SurfaceStatus::kOk) return SurfaceStatus::kBadPose;
  const std::size_t n = static_cast<std::size_t>(f.camera.width) * static_cast<std::size_t>(f.camera.height);
  if (f.depth.width != f.camera.width || f.depth.height != f.camera.height || f.depth.data.size() != n)
    return SurfaceStatus::kSizeMismatch;
  const bool has_weight = !f.weight.empty();
  if (has_weight && (f.weight.width != f.depth.width || f.weight.height != f.depth.height || f.weight.data.size() != n))
    return SurfaceStatus::kSizeMismatch;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float d = f.depth.data[i];
    if (!(d >= s.min_depth && d <= s.max_depth)) continue;
    if (has_weight && !std::isfinite(f.weight.data[i])) return SurfaceStatus::kNonFiniteValue;
    ++valid;
  }
  return valid > 0 ? SurfaceStatus::kOk : SurfaceStatus::kNoValidDepth;
}

TsdfIntegrationParams integrationParams(const VoxelGrid& grid, const DepthFrame& f, const SurfaceSettings& s) {
  TsdfIntegrationParams p{};
  for (int a = 0; a < 3; ++a) {
    p.origin[a] = static_cast<float>(grid.origin[a]);
    p.dims[a] = grid.dims[a];
  }
  p.voxel = static_cast<float>(grid.voxel);
  const Eigen::Matrix<double, 3, 4> T_cw = f.T_world_camera.inverse().matrix().topRows<3>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) p.T_cw[r * 4 + c] = static_cast<float>(T_cw(r, c));
  p.fx = static_cast<float>(f.camera.fx);
  p.fy = static_cast<float>(f.camera.fy);
  p.cx = static_cast<float>(f.camera.cx);
  p.cy = static_cast<float>(f.camera.cy);
  p.width = f.camera.width;
  p.height = f.camera.height;
  p.truncation = static_cast<float>(s.truncation);
  p.max_weight = static_cast<float>(s.max_weight);
  p.min_depth = static_cast<float>(s.min_depth);
  p.max_depth = static_cast<float>(s.max_depth);
  return p;
}

TsdfVolume::TsdfVolume(const VoxelGrid& grid, const SurfaceSettings& s)
    : grid_(grid), settings_(s), tsdf_(grid.size(), 1.f), weight_(grid.size(), 0.f) {}

void TsdfVolume::clear() {
  std::fill(tsdf_.begin(), tsdf_.end(), 1.f);
  std::fill(weight_.begin(), weight_.end(), 0.f);
}

SurfaceStatus TsdfVolume::integrate(const DepthFrame& frame) {
  const SurfaceStatus st = checkDepthFrame(frame, settings_);
  if (st != SurfaceStatus::kOk) return st;
  const TsdfIntegrationParams p = integrationParams(grid_, frame, settings_);
  const float* depth = frame.depth.data.data();
  const float* w = frame.weight.empty() ? nullptr : frame.weight.data.data();
  for (int k = 0; k < grid_.dims.z(); ++k)
    for (int j = 0; j < grid_.dims.y(); ++j) {
      const std::size_t row = grid_.index(0, j, k);
      for (int i = 0; i < grid_.dims.x(); ++i) updateVoxel(p, i, j, k, depth, w, &tsdf_[row + i], &weight_[row + i]);
    }
  return SurfaceStatus::kOk;
}

Eigen::Vector3f TsdfVolume::gradient(std::size_t g) const {
  const Eigen::Vector3i c = grid_.coords(g);
  Eigen::Vector3f grad;
  tsdfGradient(tsdf_.data(), weight_.data(), grid_.dims.x(), grid_.dims.y(), grid_.dims.z(), c.x(), c.y(), c.z(),
               grad.data());
  return grad;
}

std::size_t TsdfVolume::observedVoxels() const {
  std::size_t n = 0;
  for (float w : weight_) n += w > 0.f;
  return n;
}

}  // namespace hapi_surface
