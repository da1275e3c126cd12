// A pinhole camera with the radial-tangential lens distortion of ROS's
// plumb_bob model (OpenCV's k1, k2, p1, p2, k3; all 0: none), and the
// rigid-pose checks every core call shares. The depth images must be
// rectified (no distortion); the imaging camera's frames are projected
// with their distortion (docs/DESIGN.md "Surface", eq. S4).
#pragma once

#include "hapi_surface/surface_status.hpp"

#include <Eigen/Geometry>

namespace hapi_surface {

struct PinholeCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;

  // kOk, or kBadCamera for a zero size, non-finite / non-positive focal
  // lengths or a non-finite distortion coefficient.
  SurfaceStatus check() const;
  bool hasDistortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0; }
  // The pixel (u, v) of point p in the camera (p.z() > 0; pixel centres at
  // integers): x = p.x/p.z, y = p.y/p.z, r2 = x^2 + y^2,
  // xd = x (1 + k1 r2 + k2 r2^2 + k3 r2^3) + 2 p1 x y + p2 (r2 + 2 x^2),
  // yd = y (...) + p1 (r2 + 2 y^2) + 2 p2 x y, u = fx xd + cx, v = fy yd + cy.
  Eigen::Vector2d project(const Eigen::Vector3d& p) const;
  // Whether p lies in front and within the image's field of view widened by
  // half on each side (undistorted): where project() is meant to be used
  // (far outside it a lens model folds back into the image).
  bool nearView(const Eigen::Vector3d& p) const;
};

// kOk, or kBadPose when `T` has a non-finite entry or its rotation is not
// orthonormal within 1e-6.
SurfaceStatus checkPose(const Eigen::Isometry3d& T);

// The rotation angle (rad) and translation (m) between two poses.
double rotationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
double translationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace hapi_surface
