#include "hapi_frontend/mmse_triangulator.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace hapi_frontend {

MmseTriangulator::MmseTriangulator(const Eigen::Matrix3d& K_l, const Eigen::Matrix3d& K_r, const StereoRig& rig,
                                   double pixel_sigma, double depth_prior_factor, int iterations)
    : K_l_(K_l), K_r_(K_r), K_l_inv_(K_l.inverse()), rig_(rig), sigma_(pixel_sigma),
      depth_factor_(depth_prior_factor), iterations_(iterations) {}

MmseEstimate MmseTriangulator::estimate(const Eigen::Vector2d& ul, const Eigen::Vector2d& ur) const {
  return estimate(ul, ur, sigma_, sigma_);
}

MmseEstimate MmseTriangulator::estimate(const Eigen::Vector2d& ul, const Eigen::Vector2d& ur, double sigma_l,
                                        double sigma_r) const {
  MmseEstimate out;
  if (!(sigma_l > 0) || !(sigma_r > 0) || !ul.allFinite() || !ur.allFinite()) return out;
  const Eigen::Matrix3d Rt = rig_.R_lr.transpose();
  // Rays in the left frame; midpoint triangulation gives only the prior depth z0.
  Eigen::Vector3d rl = K_l_inv_ * Eigen::Vector3d(ul.x(), ul.y(), 1.0);
  Eigen::Vector3d rr = rig_.R_lr * (K_r_.inverse() * Eigen::Vector3d(ur.x(), ur.y(), 1.0));
  // Solve a*rl - b*rr = t (least squares).
  Eigen::Matrix<double, 3, 2> A;
  A << rl, -rr;
  Eigen::Vector2d ab = (A.transpose() * A).ldlt().solve(A.transpose() * rig_.t_lr);
  double z0 = ab(0) * rl.z();
  if (!(z0 > 0) || !std::isfinite(z0)) return out;

  // Step 1: prior along the left ray (mean x0 on the ray at the midpoint
  // depth, lateral spread = left pixel noise at range, huge spread along it).
  const Eigen::Vector3d n = rl.normalized();
  const double f = 0.5 * (K_l_(0, 0) + K_l_(1, 1));
  const Eigen::Matrix3d P = n * n.transpose();
  const Eigen::Vector3d x0 = z0 * rl;
  const double sz = depth_factor_ * z0;
  const Eigen::Matrix2d Rm = sigma_r * sigma_r * Eigen::Matrix2d::Identity();
  // Right projection h(x) and its Jacobian; false when behind the right camera.
  auto project = [&](const Eigen::Vector3d& x, Eigen::Vector2d* h, Eigen::Matrix<double, 2, 3>* J) {
    const Eigen::Vector3d q = K_r_ * (Rt * (x - rig_.t_lr));
    if (!(q.z() > 0)) return false;
    *h = Eigen::Vector2d(q.x() / q.z(), q.y() / q.z());
    Eigen::Matrix<double, 2, 3> dpi;  // d(pi)/dq
    dpi << 1 / q.z(), 0, -q.x() / (q.z() * q.z()), 0, 1 / q.z(), -q.y() / (q.z() * q.z());
    *J = dpi * K_r_ * Rt;
    return true;
  };
  Eigen::Vector3d x = x0;
  Eigen::Vector2d h;
  Eigen::Matrix<double, 2, 3> J;
  Eigen::Matrix3d C0;
  double zc = z0;  // depth at which the lateral spread is evaluated
  for (int pass = 0; pass < 2; ++pass) {
    const double lat = zc * rl.norm() * sigma_l / f;
    C0 = lat * lat * (Eigen::Matrix3d::Identity() - P) + sz * sz * P;
    // Step 2: iterated EKF update with the right pixel.
    x = x0;
    for (int it = 0; it < iterations_; ++it) {
      if (!project(x, &h, &J)) return out;
      const Eigen::Matrix2d S = J * C0 * J.transpose() + Rm;
      const Eigen::Matrix<double, 3, 2> G = C0 * J.transpose() * S.inverse();
      const Eigen::Vector3d xn = x0 + G * (ur - h - J * (x0 - x));
      const bool done = (xn - x).norm() < 1e-9 * (1.0 + x.norm());
      x = xn;
      if (done) break;
    }
    if (!(x.z() > 0) || !x.allFinite()) return out;
    zc = x.z();
  }
  // Final information: prior + right measurement, Jacobian at the converged point.
  if (!project(x, &h, &J)) return out;
  const Eigen::Matrix3d info = C0.inverse() + J.transpose() * Rm.inverse() * J;
  out.covariance = info.inverse();
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  out.position = x;
  out.valid = out.position.allFinite() && out.covariance.allFinite();
  return out;
}

}  // namespace hapi_frontend
