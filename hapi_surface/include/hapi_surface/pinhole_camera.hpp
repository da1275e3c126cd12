// A pinhole camera without distortion (rectified images; the imaging
// camera's frames are undistorted by the caller or taken as pinhole) and the
// rigid-pose checks every core call shares.
#pragma once

#include "hapi_surface/surface_status.hpp"

#include <Eigen/Geometry>

namespace hapi_surface {

struct PinholeCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;

  // kOk, or kBadCamera for a zero size or non-finite / non-positive focal lengths.
  SurfaceStatus check() const;
};

// kOk, or kBadPose when `T` has a non-finite entry or its rotation is not
// orthonormal within 1e-6.
SurfaceStatus checkPose(const Eigen::Isometry3d& T);

// The rotation angle (rad) and translation (m) between two poses.
double rotationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
double translationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace hapi_surface
