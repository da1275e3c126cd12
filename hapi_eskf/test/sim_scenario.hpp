// Simulated stereo SLAM scenario for the filter tests: random 3D points with
// random 32-byte descriptors, a camera that follows the filter's own motion
// model (constant velocity + random-walk accelerations), and 3D measurements
// with a stereo noise model (lateral sigma ~ depth, along-ray sigma ~ depth^2).
#pragma once

#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/so3.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Cholesky>

#include <random>
#include <vector>

namespace hapi_eskf {
namespace sim {

struct StereoRig {
  double focal_px = 450.0;
  double baseline_m = 0.12;
  double sigma_px = 0.5;      // keypoint / disparity noise
  double min_depth = 1.5, max_depth = 14.0;
  double tan_half_fov_x = 0.7, tan_half_fov_y = 0.5;

  // Covariance of a stereo point at camera-frame position z: along the ray
  // sigma = d^2 sigma_px / (f b), across it sigma = d sigma_px / f.
  Mat3 covariance(const Vec3& z) const {
    const double d = z.z();
    const double s_perp = d * sigma_px / focal_px;
    const double s_along = d * d * sigma_px / (focal_px * baseline_m);
    const Vec3 u = z.normalized();
    return s_perp * s_perp * Mat3::Identity() + (s_along * s_along - s_perp * s_perp) * u * u.transpose();
  }
  bool visible(const Vec3& z) const {
    return z.z() > min_depth && z.z() < max_depth && std::abs(z.x()) < tan_half_fov_x * z.z() &&
           std::abs(z.y()) < tan_half_fov_y * z.z();
  }
};

struct World {
  std::vector<Vec3> points;
  std::vector<std::vector<uint8_t>> descriptors;  // 32 bytes each
};

inline World randomWorld(std::mt19937& rng, int n, const Vec3& lo, const Vec3& hi) {
  World w;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < n; ++i) {
    w.points.push_back(lo + (hi - lo).cwiseProduct(drawVec3(u, rng)));
    std::vector<uint8_t> d(32);
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    w.descriptors.push_back(d);
  }
  return w;
}

// One ground-truth step of the filter's motion model with random accelerations
// of density sigma_a / sigma_alpha (the filter is told these same densities).
inline PoseState truthStep(const PoseState& x, double dt, const EskfSettings& s, std::mt19937& rng) {
  PoseState y = predictPose(x, dt, s);
  std::normal_distribution<double> g(0.0, 1.0);
  const double sv = s.sigma_acceleration * std::sqrt(dt), sw = s.sigma_angular_acceleration * std::sqrt(dt);
  y.v += sv * drawVec3(g, rng);
  y.w += sw * drawVec3(g, rng);
  return y;
}

// Noisy frame of everything visible from `truth`; `bit_flips` random bits of
// each descriptor are flipped per observation (so association has work to do).
inline StereoFrame makeFrame(const World& w, const PoseState& truth, const StereoRig& rig, double stamp,
                             int bit_flips, std::mt19937& rng) {
  StereoFrame f;
  f.stamp = stamp;
  f.descriptor_length = 32;
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_int_distribution<int> bit(0, 255);
  std::uniform_real_distribution<float> resp(0.f, 1.f);
  for (std::size_t i = 0; i < w.points.size(); ++i) {
    const Vec3 zc = measure(truth, w.points[i]);
    if (!rig.visible(zc)) continue;
    StereoMeasurement m;
    m.Cz = rig.covariance(zc);
    const Mat3 L = m.Cz.llt().matrixL();
    m.z = zc + L * drawVec3(g, rng);
    m.frontend_id = static_cast<uint32_t>(i);
    m.response = resp(rng);
    f.measurements.push_back(m);
    std::vector<uint8_t> d = w.descriptors[i];
    for (int b = 0; b < bit_flips; ++b) {
      const int k = bit(rng);
      d[k / 8] ^= static_cast<uint8_t>(1u << (k % 8));
    }
    f.descriptors.insert(f.descriptors.end(), d.begin(), d.end());
  }
  return f;
}

// Error of the estimate in the filter's convention: [p - p^, Log(R^^T R)].
inline Eigen::Matrix<double, 6, 1> poseError(const PoseState& truth, const PoseState& est) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = truth.p - est.p;
  e.tail<3>() = logSO3(est.q.toRotationMatrix().transpose() * truth.q.toRotationMatrix());
  return e;
}

}  // namespace sim
}  // namespace hapi_eskf
