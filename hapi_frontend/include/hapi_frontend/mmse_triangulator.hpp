// Two-step MMSE stereo point estimate (thesis Algorithm 2.1, corrected).
//
// Step 1 (left camera): the left observation only constrains the point to its
// ray r = K_l^-1 [u_l; 1]. We encode that as a Gaussian prior
//   x0 = z0 * r,  C0 = (z0*sigma/f_l)^2 (I - n n^T) + sigma_z^2 n n^T,  n = r/|r|,
// i.e. the lateral spread of one pixel at depth z0 plus a very large variance
// along the ray (sigma_z = depth_prior_factor * z0), so the prior depth z0 (from
// a linear midpoint triangulation) has no practical influence on the result.
// Step 2 (right camera): measurement h(x) = pi(K_r R_lr^T (x - t_lr)) with noise
// sigma^2 I. Iterated EKF (= Gauss-Newton on prior + measurement):
//   x_{i+1} = x0 + C0 J^T (J C0 J^T + R)^-1 (z - h(x_i) - J (x0 - x_i)).
// Covariance from the final information: C = (C0^-1 + J^T R^-1 J)^-1.
// The lateral prior spread depends on the depth; it is evaluated at the
// midpoint depth first and once more at the converged depth (second pass).
#pragma once

#include "hapi_frontend/camera_model.hpp"

#include <Eigen/Core>

namespace hapi_frontend {

struct MmseEstimate {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // left camera frame [m]
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  bool valid = false;  // false: behind a camera / did not converge
};

class MmseTriangulator {
 public:
  MmseTriangulator(const Eigen::Matrix3d& K_l, const Eigen::Matrix3d& K_r, const StereoRig& rig, double pixel_sigma,
                   double depth_prior_factor = 10.0, int iterations = 5);
  // Both pixels with the constructor's pixel_sigma.
  MmseEstimate estimate(const Eigen::Vector2d& u_left, const Eigen::Vector2d& u_right) const;
  // Per-observation noise [px, 1 sigma], e.g. scaled with the pyramid level
  // the keypoint was detected on.
  MmseEstimate estimate(const Eigen::Vector2d& u_left, const Eigen::Vector2d& u_right, double sigma_left,
                        double sigma_right) const;

 private:
  Eigen::Matrix3d K_l_, K_r_, K_l_inv_;
  StereoRig rig_;
  double sigma_, depth_factor_;
  int iterations_;
};

}  // namespace hapi_frontend
