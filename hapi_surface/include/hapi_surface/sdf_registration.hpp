// Registration of a depth frame to the fused surface (docs/SURFACE.md
// "Settle rule", eq. R1): the camera pose that brings the frame's depth points
// onto the zero level of the TSDF, by Gauss-Newton on their interpolated
// signed distances. Only points inside the truncation band of voxels seen
// often enough count, so the pose must start within about the truncation
// distance. Directions the surface does not constrain (along a plane, along
// and around a cylinder's axis) keep the starting pose.
#pragma once

#include "hapi_surface/tsdf_volume.hpp"

#include <Eigen/Geometry>

#include <cstddef>

namespace hapi_surface {

struct Registration {
  bool accepted = false;            // points >= registration_min_points, median |distance| within bounds
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  std::size_t points = 0;           // depth points inside the band at the result
  double median_distance = 0;       // median |signed distance| of those points at the result, m
  int iterations = 0;
};

// The signed distance (m, positive in front of the surface) and its
// gradient at world point p, trilinear in the 8 voxels around it; false
// when one of them is seen less than mesh_min_weight times or lies at the
// truncation (no gradient there) or p is outside the grid.
bool sampleSignedDistance(const TsdfVolume& volume, const Eigen::Vector3d& p, double* distance,
                          Eigen::Vector3d* gradient);

// Registers `frame` (starting at its T_world_camera) to `volume`, with the
// volume's settings (registration_*).
Registration registerToSurface(const TsdfVolume& volume, const DepthFrame& frame);

}  // namespace hapi_surface
