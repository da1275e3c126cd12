// A body moving on an analytic trajectory with an IMU and a stereo camera for
// the inertial filter tests: exact pose, velocity, acceleration and angular
// rate at any time, IMU samples (specific force and rate in the body frame
// with white noise and constant biases) and the camera through a non-identity
// extrinsic. World: z up, gravity (0, 0, -9.81).
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "hapi_eskf/so3.hpp"
#include "sim_scenario.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace hapi_eskf {
namespace sim {

struct BodyTruth {
  Vec3 p, v, a;          // world [m], [m/s], [m/s^2]
  Eigen::Quaterniond q;  // body -> world
  Vec3 omega;            // body-frame angular rate [rad/s]
};

// Still for `rest` seconds, then a smooth motion (amplitudes in m and rad,
// a C2 ramp-in over 1 s so velocity and acceleration start at zero).
struct InertialTrajectory {
  double rest = 0.5;
  Vec3 amp_p = Vec3(0.3, 0.2, 0.1), freq_p = Vec3(0.31, 0.43, 0.57);  // [m], [Hz]
  Vec3 amp_r = Vec3(0.25, 0.2, 0.35), freq_r = Vec3(0.37, 0.29, 0.23);  // [rad], [Hz]

  // Ramp s(u) = u^3 (10 - 15 u + 6 u^2), u in [0, 1]: s, s', s'' vanish at 0.
  static void ramp(double u, double* s, double* ds, double* dds) {
    if (u <= 0.0) {
      *s = *ds = *dds = 0.0;
    } else if (u >= 1.0) {
      *s = 1.0;
      *ds = *dds = 0.0;
    } else {
      *s = u * u * u * (10 - 15 * u + 6 * u * u);
      *ds = 30 * u * u * (1 - u) * (1 - u);
      *dds = 60 * u * (1 - u) * (1 - 2 * u);
    }
  }

  // f(t) = amp * ramp(t - rest) * sin(2 pi freq (t - rest)) per component,
  // with its first two derivatives.
  static void signal(const Vec3& amp, const Vec3& freq, double tau, Vec3* f, Vec3* df, Vec3* ddf) {
    double s, ds, dds;
    ramp(tau, &s, &ds, &dds);
    for (int i = 0; i < 3; ++i) {
      const double w = 2 * M_PI * freq[i];
      const double sn = std::sin(w * tau), cs = std::cos(w * tau);
      const double g = tau > 0 ? sn : 0.0, dg = tau > 0 ? w * cs : 0.0, ddg = tau > 0 ? -w * w * sn : 0.0;
      (*f)[i] = amp[i] * s * g;
      (*df)[i] = amp[i] * (ds * g + s * dg);
      (*ddf)[i] = amp[i] * (dds * g + 2 * ds * dg + s * ddg);
    }
  }

  BodyTruth at(double t) const {
    const double tau = t - rest;
    BodyTruth b;
    signal(amp_p, freq_p, tau, &b.p, &b.v, &b.a);
    Vec3 phi, dphi, ddphi;
    signal(amp_r, freq_r, tau, &phi, &dphi, &ddphi);
    b.q = quatExp(phi);
    b.omega = rightJacobianSO3(phi) * dphi;  // R = Exp(phi): R^T dR/dt = [J_r(phi) dphi]x
    return b;
  }
};

struct ImuNoiseModel {
  double gyro_density = 1.7e-4, accel_density = 2.0e-3;  // EuRoC's ADIS16448
  Vec3 b_g = Vec3(0.004, -0.003, 0.002), b_a = Vec3(0.05, -0.04, 0.03);
};

inline const Vec3 kGravity(0, 0, -9.81);

// One IMU sample at t (period dt for the white-noise variance).
inline ImuSample imuSample(const InertialTrajectory& traj, const ImuNoiseModel& n, double t, double dt,
                           std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const BodyTruth b = traj.at(t);
  const Mat3 R = b.q.toRotationMatrix();
  ImuSample s;
  s.stamp = t;
  s.gyro = b.omega + n.b_g + n.gyro_density / std::sqrt(dt) * drawVec3(g, rng);
  s.accel = R.transpose() * (b.a - kGravity) + n.b_a + n.accel_density / std::sqrt(dt) * drawVec3(g, rng);
  return s;
}

// The samples of an IMU at period dt from sample *k on, up to time t (the
// ones a filter takes before the frame at t); *k moves past them. The
// noise is drawn in sample order, as one imuSample() call each.
inline std::vector<ImuSample> imuSamplesUpTo(const InertialTrajectory& traj, const ImuNoiseModel& n, double t, int* k,
                                             std::mt19937& rng, double dt = 0.005) {
  std::vector<ImuSample> out;
  for (; *k * dt <= t + 1e-9; ++*k) out.push_back(imuSample(traj, n, *k * dt, dt, rng));
  return out;
}

// The camera pose of a body truth through the extrinsic.
inline PoseState cameraOf(const BodyTruth& b, const CameraExtrinsic& e) {
  PoseState c;
  c.q = b.q * Eigen::Quaterniond(e.R_imu_cam);
  c.p = b.p + b.q.toRotationMatrix() * e.p_imu_cam;
  return c;
}

// A REP-103 body (x forward, z up) carrying an optical camera (z forward,
// x right, y down) a few cm off its origin.
inline CameraExtrinsic forwardCamera() {
  CameraExtrinsic e;
  e.R_imu_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  e.p_imu_cam = Vec3(0.05, 0.02, -0.01);
  return e;
}

// A generic inertial state with a sample (Jacobian tests): biases, a
// tilted gravity, the forward camera's extrinsic and a time offset.
inline NominalState someState() {
  NominalState x;
  x.p = Vec3(0.3, -0.2, 1.1);
  x.q = quatExp(Vec3(0.3, -0.5, 0.8));
  x.v = Vec3(0.4, -0.1, 0.2);
  x.b_g = Vec3(0.01, -0.02, 0.005);
  x.b_a = Vec3(0.1, 0.05, -0.08);
  x.g = Vec3(0.05, -0.02, -9.8);
  x.w = Vec3(0.7, -0.4, 1.1);
  x.f = Vec3(0.5, 9.6, -1.2);
  x.has_imu = true;
  const CameraExtrinsic e = forwardCamera();
  x.R_bc = e.R_imu_cam;
  x.p_bc = e.p_imu_cam;
  x.t_d = 0.003;
  return x;
}

// The camera's error [dp, dtheta, dv, dw] between two camera views.
inline Eigen::Matrix<double, 12, 1> cameraError(const PoseState& c, const PoseState& c0) {
  Eigen::Matrix<double, 12, 1> e;
  e << c.p - c0.p, logSO3(c0.q.toRotationMatrix().transpose() * c.q.toRotationMatrix()), c.v - c0.v, c.w - c0.w;
  return e;
}

// d f(x (+) d) / d by central differences over the model's error state
// (rows: f's length, P columns).
template <typename Function>
Eigen::MatrixXd centralDifferences(const MotionModel& m, const NominalState& x, int rows, Function f) {
  const int P = m.poseDim();
  Eigen::MatrixXd J(rows, P);
  const double h = 1e-6;
  for (int i = 0; i < P; ++i) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(P);
    d(i) = h;
    NominalState xp = x, xm = x;
    m.inject(&xp, d);
    m.inject(&xm, -d);
    J.col(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

// d(camera error of m.camera(x (+) d)) / d, 12 x P: the numeric counterpart
// of MotionModel::cameraStateJacobian.
inline Eigen::MatrixXd numericCameraStateJacobian(const MotionModel& m, const NominalState& x) {
  const PoseState c0 = m.camera(x);
  return centralDifferences(m, x, 12, [&](const NominalState& xi) -> Eigen::VectorXd {
    return cameraError(m.camera(xi), c0);
  });
}

// A random SPD matrix (n x n) for covariance tests.
inline Eigen::MatrixXd randomCovariance(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = 0.1 * g(rng);
  return A * A.transpose() + 0.01 * Eigen::MatrixXd::Identity(n, n);
}

}  // namespace sim
}  // namespace hapi_eskf
