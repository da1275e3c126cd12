// A scene with no direction a rigid motion can slide along: two balls of
// different size on a plane, 27 cm from cameras around the origin, and the
// exact distance of a point to it (for mesh errors).
#pragma once

#include "synthetic_scene.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_surface {
namespace test {

struct TwoBalls {
  Eigen::Vector3d centre{0, 0, 0.27};
  Eigen::Vector3d ball_a{-0.012, 0.004, 0.262}, ball_b{0.014, -0.006, 0.266};
  double radius_a = 0.012, radius_b = 0.008, plane_z = 0.272;

  Scene scene() const {
    Scene s;
    s.addPlane(Eigen::Vector3d(0, 0, 1), plane_z);
    s.addSphere(ball_a, radius_a);
    s.addSphere(ball_b, radius_b);
    return s;
  }
  // Distance to the visible surface (the union of the solids' boundaries).
  double distance(const Eigen::Vector3d& p) const {
    const double a = (p - ball_a).norm() - radius_a, b = (p - ball_b).norm() - radius_b, c = p.z() - plane_z;
    return std::min({std::abs(a), std::abs(b), std::abs(c)});
  }
  // Cameras 27 cm above the plane, spread over +-3 cm, looking at the centre.
  std::vector<Eigen::Isometry3d> cameras(int n) const {
    std::vector<Eigen::Isometry3d> poses;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      poses.push_back(lookAt(Eigen::Vector3d(0.03 * std::cos(a), 0.03 * std::sin(a), 0), centre));
    }
    return poses;
  }
  // 1 mm voxels, 6 mm truncation (the skin profile), 8 x 8 x 6 cm.
  static SurfaceSettings settings() {
    SurfaceSettings s = volumeOf(0.08, 0.08, 0.06);
    s.voxel_size = 0.001;
    s.truncation = 0.006;
    return s;
  }
};

// `T` moved by `shift` (world) and turned by `angle` about the world axis `axis` through its centre.
inline Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T, const Eigen::Vector3d& shift, double angle,
                                   const Eigen::Vector3d& axis) {
  Eigen::Isometry3d out = T;
  out.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix() * T.linear();
  out.translation() += shift;
  return out;
}

}  // namespace test
}  // namespace hapi_surface
