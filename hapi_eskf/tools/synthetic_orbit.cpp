// The synthetic orbit scenario (synthetic_orbit.hpp).
#include "synthetic_orbit.hpp"
#include "hapi_eskf/random_draw.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace hapi_eskf {
namespace tools {

LandmarkStream makeSyntheticOrbit(const SyntheticOrbitOptions& o) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255), bit(0, 255);
  std::uniform_real_distribution<float> uni(0.f, 1.f);
  std::vector<Vec3> X(o.points);
  std::vector<std::array<uint8_t, 32>> D(o.points);
  for (int i = 0; i < o.points; ++i) {
    X[i] = o.globe_radius * drawVec3(g, rng).normalized();
    for (auto& b : D[i]) b = static_cast<uint8_t>(byte(rng));
  }
  LandmarkStream s;
  s.has_globe = true;
  s.globe_centre = Vec3::Zero();
  s.globe_radius = o.globe_radius;
  for (int k = 0; k < o.frames; ++k) {
    const double t = k / o.rate_hz, phi = 2 * M_PI * k / o.frames;
    // Camera on a circle in the x-y plane, z (optical axis) towards the
    // centre, y (image down) along -z of the world.
    const Vec3 p = o.orbit_radius * Vec3(std::cos(phi), std::sin(phi), 0.0);
    const Vec3 ez = -p.normalized(), ey(0, 0, -1), ex = ey.cross(ez);
    Mat3 R;
    R << ex, ey, ez;
    TruePose tp;
    tp.t = t;
    tp.p = p;
    tp.q = Eigen::Quaterniond(R);
    s.truth.push_back(tp);
    StereoFrame f;
    f.stamp = t;
    f.descriptor_length = 32;
    std::vector<int> visible;
    for (int i = 0; i < o.points; ++i) {
      const Vec3 z = R.transpose() * (X[i] - p);
      const Vec3 normal = X[i].normalized();
      if (z.z() <= 0.05 || std::abs(z.x()) > o.tan_half_fov * z.z() || std::abs(z.y()) > o.tan_half_fov * z.z())
        continue;
      if (normal.dot((p - X[i]).normalized()) < 0.3) continue;  // facing away / grazing
      visible.push_back(i);
    }
    std::shuffle(visible.begin(), visible.end(), rng);
    if (static_cast<int>(visible.size()) > o.max_measurements) visible.resize(o.max_measurements);
    for (int i : visible) {
      const Vec3 zt = R.transpose() * (X[i] - p);
      const double d = zt.z();
      const double s_perp = d * o.sigma_px / o.focal_px, s_along = d * d * o.sigma_px / (o.focal_px * o.baseline_m);
      const Vec3 u = zt.normalized();
      StereoMeasurement m;
      m.Cz = s_perp * s_perp * Mat3::Identity() + (s_along * s_along - s_perp * s_perp) * u * u.transpose();
      const Mat3 L = m.Cz.llt().matrixL();
      m.z = zt + L * drawVec3(g, rng);
      m.frontend_id = static_cast<uint32_t>(i);
      m.response = uni(rng);
      m.rgb = {{static_cast<uint8_t>(i % 256), 128, 128}};
      f.measurements.push_back(m);
      std::array<uint8_t, 32> desc = D[i];
      for (int b = 0; b < o.bit_flips; ++b) {
        const int j = bit(rng);
        desc[j / 8] ^= static_cast<uint8_t>(1u << (j % 8));
      }
      f.descriptors.insert(f.descriptors.end(), desc.begin(), desc.end());
    }
    s.frames.push_back(std::move(f));
  }
  return s;
}

}  // namespace tools
}  // namespace hapi_eskf
