// A synthetic skin scan for the surface-motion tests: a plane z = depth in
// the world (the first camera frame), landmarks on it, a camera translating
// parallel to it (or held still) and the skin sliding in it, the odometry
// (with a velocity bias if asked) at 200 Hz and the image flow of the
// measurement pixel at 40 Hz, with Gaussian pixel noise and a latency.
#pragma once

#include "hapi_eskf/surface_motion/surface_motion_estimator.hpp"

#include <functional>
#include <random>
#include <vector>

namespace hapi_eskf {
namespace surface_motion {
namespace test {

inline ImagingCamera testCamera() {
  ImagingCamera c;
  c.fx = c.fy = 500;
  c.cx = 319.5;
  c.cy = 239.5;
  c.width = 640;
  c.height = 480;
  c.frame_rate = 40;
  return c;
}

// Landmarks on the plane z = depth, a grid with `sigma` noise along z.
inline std::vector<Vec3> planeLandmarks(double depth, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> n(0, sigma);
  std::vector<Vec3> out;
  for (double x = -0.1; x <= 0.1001; x += 0.01)
    for (double y = -0.08; y <= 0.0801; y += 0.01) out.emplace_back(x, y, depth + n(rng));
  return out;
}

struct ScanConfig {
  double depth = 0.3;           // [m]
  double duration = 4.0;        // [s]
  double odom_rate = 200, flow_rate = 40;
  double flow_sigma = 0.02;     // [px] per axis
  double flow_latency = 0.012;  // [s] after the frame's stamp
  Vec3 odom_velocity_bias = Vec3::Zero();  // [m/s] the odometry's error
  double odom_rate_noise = 0;              // [rad/s] white noise on the odometry's w, per axis (a gyro's)
  // [m] per axis: the odometry's position jumps by this much (Gaussian) at
  // every 10 Hz frame, as the filter's corrections do.
  double odom_position_jump = 0;
  std::function<Vec3(double)> device_velocity = [](double) { return Vec3::Zero(); };   // world [m/s]
  std::function<Vec3(double)> subject_velocity = [](double) { return Vec3::Zero(); };  // world, in the plane [m/s]
  unsigned seed = 1;
  bool fuse_flow = true;
};

struct ScanSample {
  double t;
  Vec3 truth_s;  // [mm/s] the true on-surface velocity
  SurfaceMotionOutput out;
};

// Runs the estimator over the scan: odometry and flows in stamp order of
// arrival, the flow of [t0, t1] delivered flow_latency after t1.
inline std::vector<ScanSample> runScan(const ScanConfig& c, SurfaceMotionEstimator* est) {
  std::mt19937 rng(c.seed);
  std::normal_distribution<double> noise(0, c.flow_sigma), unit(0, 1);
  const ImagingCamera cam = est->camera();
  const Vec3 ray = cam.ray(est->pixel());
  const int per_frame = static_cast<int>(std::lround(c.odom_rate / c.flow_rate));
  const double h = 1.0 / c.odom_rate;
  const int steps = static_cast<int>(c.duration * c.odom_rate);
  // True camera positions and the skin's displacement, by midpoint sums.
  std::vector<Vec3> p(steps + 1, Vec3::Zero()), p_odom(steps + 1, Vec3::Zero()), slide(steps + 1, Vec3::Zero());
  std::normal_distribution<double> jump(0, 1);
  const int per_correction = static_cast<int>(std::lround(c.odom_rate / 10));
  for (int k = 0; k < steps; ++k) {
    const double tm = (k + 0.5) * h;
    p[k + 1] = p[k] + h * c.device_velocity(tm);
    p_odom[k + 1] = p_odom[k] + h * (c.device_velocity(tm) + c.odom_velocity_bias);
    if ((k + 1) % per_correction == 0) p_odom[k + 1] += c.odom_position_jump * Vec3(jump(rng), jump(rng), jump(rng));
    slide[k + 1] = slide[k] + h * c.subject_velocity(tm);
  }
  struct Flow {
    double arrival;
    FlowMeasurement f;
  };
  std::vector<Flow> flows;
  for (int k1 = per_frame; k1 <= steps; k1 += per_frame) {
    const int k0 = k1 - per_frame;
    // The skin point on the ray at t0, where its material sits at t1.
    const Vec3 Xw0 = p[k0] + c.depth / ray.z() * ray;
    const Vec3 Xc1 = Xw0 + (slide[k1] - slide[k0]) - p[k1];
    FlowMeasurement f;
    f.t_prev = k0 * h;
    f.t = k1 * h;
    const Vec2 px = est->pixel();
    f.u = px.x();
    f.v = px.y();
    const Vec2 d = cam.project(Xc1) - cam.project(Xw0 - p[k0]);
    f.affine = {d.x() + noise(rng), d.y() + noise(rng), 0, 0, 0, 0};
    for (int i = 0; i < 6; ++i) f.covariance[i * 7] = c.flow_sigma * c.flow_sigma;
    f.inliers = f.tracked = 30;
    flows.push_back({f.t + c.flow_latency, f});
  }
  std::vector<ScanSample> out;
  std::size_t next_flow = 0;
  for (int k = 0; k <= steps; ++k) {
    const double t = k * h;
    while (c.fuse_flow && next_flow < flows.size() && flows[next_flow].arrival <= t) est->addFlow(flows[next_flow++].f);
    CameraOdometry o;
    o.t = t;
    o.T_world_cam.translation() = p_odom[k];
    o.v = c.device_velocity(t) + c.odom_velocity_bias;
    if (c.odom_rate_noise > 0) o.w = c.odom_rate_noise * Vec3(unit(rng), unit(rng), unit(rng));
    o.twist_covariance = 1e-6 * Mat6::Identity();
    const auto r = est->addOdometry(o);
    if (!r) continue;
    // Camera axes = world axes; normal -z, ray at the pixel: s is Xdot less its part along the ray.
    const Vec3 Xd = c.subject_velocity(t) - c.device_velocity(t);
    const Vec3 n(0, 0, -1);
    const Vec3 s = Xd - ray * Xd.dot(n) / ray.dot(n);
    out.push_back({t, 1000.0 * s, *r});
  }
  return out;
}

// RMS of |estimate - truth| of the OK samples after `settle` s [mm/s].
inline double rmsError(const std::vector<ScanSample>& run, double settle) {
  double sum = 0;
  int n = 0;
  for (const ScanSample& s : run) {
    if (s.t < settle || s.out.status != MotionStatus::kOk) continue;
    sum += (s.out.velocity.surface_velocity - s.truth_s).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : std::numeric_limits<double>::infinity();
}

}  // namespace test
}  // namespace surface_motion
}  // namespace hapi_eskf
