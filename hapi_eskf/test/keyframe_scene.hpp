// A mapped surface for the keyframe tests and benchmark: landmarks with
// random 32-byte descriptors on a plane, and stereo views of it (a pinhole's
// field of view, point noise, descriptor bits flipped per view).
#pragma once

#include "hapi_eskf/keyframes/keyframe.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace hapi_eskf {
namespace test {

struct KeyframeScene {
  std::vector<Vec3> landmarks;                    // map frame, on the plane z = 0 [m]
  std::vector<std::vector<std::uint8_t>> descriptors;
};

// n landmarks spread uniformly over a side x side square about the origin.
inline KeyframeScene makeKeyframeScene(int n, double side, unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-0.5 * side, 0.5 * side);
  std::uniform_int_distribution<int> byte(0, 255);
  KeyframeScene s;
  for (int i = 0; i < n; ++i) {
    s.landmarks.emplace_back(u(g), u(g), 0.0);
    std::vector<std::uint8_t> d(32);
    for (auto& b : d) b = static_cast<std::uint8_t>(byte(g));
    s.descriptors.push_back(std::move(d));
  }
  return s;
}

// A camera at height h above (x, y), looking down (optical axis -z of the
// map), turned by yaw about it.
inline Eigen::Isometry3d cameraAbove(double x, double y, double h, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(M_PI, Vec3::UnitX())).toRotationMatrix();
  T.translation() = Vec3(x, y, h);
  return T;
}

// The stereo frame a camera at T_map_cam takes: every landmark inside a 60 x
// 45 deg field of view, its position with noise (0.3 mm across the ray, 1 mm
// along it) and `flips` random descriptor bits changed.
inline StereoFrame viewOf(const KeyframeScene& s, const Eigen::Isometry3d& T_map_cam, std::mt19937& g, int flips,
                          double stamp = 0.0) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_int_distribution<int> bit(0, 255);
  const double tx = std::tan(30.0 * M_PI / 180), ty = std::tan(22.5 * M_PI / 180);
  StereoFrame f;
  f.stamp = stamp;
  f.descriptor_length = 32;
  const Eigen::Isometry3d T_cam_map = T_map_cam.inverse();
  for (std::size_t i = 0; i < s.landmarks.size(); ++i) {
    const Vec3 p = T_cam_map * s.landmarks[i];
    if (p.z() <= 0.05 || std::abs(p.x()) > tx * p.z() || std::abs(p.y()) > ty * p.z()) continue;
    StereoMeasurement m;
    m.Cz = Vec3(0.3e-3 * 0.3e-3, 0.3e-3 * 0.3e-3, 1e-3 * 1e-3).asDiagonal();
    m.z = p + Vec3(0.3e-3 * n(g), 0.3e-3 * n(g), 1e-3 * n(g));
    m.frontend_id = static_cast<std::uint32_t>(f.measurements.size());
    f.measurements.push_back(m);
    std::vector<std::uint8_t> d = s.descriptors[i];
    for (int k = 0; k < flips; ++k) {
      const int b = bit(g);
      d[b / 8] ^= static_cast<std::uint8_t>(1u << (b % 8));
    }
    f.descriptors.insert(f.descriptors.end(), d.begin(), d.end());
  }
  return f;
}

}  // namespace test
}  // namespace hapi_eskf
