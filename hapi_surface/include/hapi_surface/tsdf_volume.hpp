// A bounded, dense TSDF volume (docs/DESIGN.md "Surface", eq. S1-S3):
// origin, voxel size and dimensions fixed at construction, one (tsdf,
// weight) pair of floats per voxel, tsdf in [-1, 1] in units of the
// truncation distance, weight 0 = never observed.
#pragma once

#include "hapi_surface/float_image.hpp"
#include "hapi_surface/pinhole_camera.hpp"
#include "hapi_surface/surface_settings.hpp"
#include "hapi_surface/tsdf_math.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace hapi_surface {

// The grid: world position of voxel (0,0,0)'s corner, edge, counts.
struct VoxelGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double voxel = 0.0005;
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();

  std::size_t size() const {
    return static_cast<std::size_t>(dims.x()) * static_cast<std::size_t>(dims.y()) * static_cast<std::size_t>(dims.z());
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * dims.y() + j) * static_cast<std::size_t>(dims.x()) + i;
  }
  // (i, j, k) of a linear index.
  Eigen::Vector3i coords(std::size_t g) const {
    const std::size_t nx = dims.x(), ny = dims.y();
    return Eigen::Vector3i(static_cast<int>(g % nx), static_cast<int>((g / nx) % ny), static_cast<int>(g / (nx * ny)));
  }
  // Centre of voxel (i, j, k) in the world (the TSDF samples live there).
  Eigen::Vector3d centre(int i, int j, int k) const {
    return origin + voxel * (Eigen::Vector3d(i, j, k) + Eigen::Vector3d::Constant(0.5));
  }
  // The grid of `s`'s size, centred at `centre`.
  static VoxelGrid centredAt(const Eigen::Vector3d& centre, const SurfaceSettings& s);
};

// One depth frame: depth in metres (NaN, inf, 0 = no measurement, REP-118),
// an optional per-pixel weight (empty = 1; a valid depth pixel's weight must
// be finite, <= 0 skips the pixel), the camera and its pose in the world.
struct DepthFrame {
  FloatImage depth;
  FloatImage weight;
  PinholeCamera camera;
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
};

// kOk when `frame` can be integrated with `s`: camera and pose valid, sizes
// agree, some depth within [min_depth, max_depth], finite weights.
SurfaceStatus checkDepthFrame(const DepthFrame& frame, const SurfaceSettings& s);

// The kernel parameters of one frame (shared by the CPU and CUDA paths).
TsdfIntegrationParams integrationParams(const VoxelGrid& grid, const DepthFrame& frame, const SurfaceSettings& s);

class TsdfVolume {
 public:
  TsdfVolume(const VoxelGrid& grid, const SurfaceSettings& s);

  // Fuses one frame (checkDepthFrame first: on error nothing changes).
  SurfaceStatus integrate(const DepthFrame& frame);
  // Back to never observed.
  void clear();

  const VoxelGrid& grid() const { return grid_; }
  const SurfaceSettings& settings() const { return settings_; }
  const std::vector<float>& tsdf() const { return tsdf_; }
  const std::vector<float>& weight() const { return weight_; }
  // For the CUDA path, which writes its result back.
  std::vector<float>& mutableTsdf() { return tsdf_; }
  std::vector<float>& mutableWeight() { return weight_; }
  // The TSDF gradient at voxel g (per voxel, central differences; one-sided
  // at the border or next to an unobserved voxel): points out of the
  // surface, towards free space.
  Eigen::Vector3f gradient(std::size_t g) const;
  // Observed voxels (weight > 0).
  std::size_t observedVoxels() const;

 private:
  VoxelGrid grid_;
  SurfaceSettings settings_;
  std::vector<float> tsdf_, weight_;
};

}  // namespace hapi_surface
