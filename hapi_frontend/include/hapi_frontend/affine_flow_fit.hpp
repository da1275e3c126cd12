// Robust fit of a local affine flow field to tracked feature displacements
// (docs/DESIGN.md "Surface motion: image flow"). Plain Eigen, no OpenCV.
//
// Model about the pixel c = (u, v), for a feature at x in the earlier frame
// that moved by d:
//   d_u = a0 + a2 (x_u - u) + a3 (x_v - v)
//   d_v = a1 + a4 (x_u - u) + a5 (x_v - v)
// (the parameter order of hapi_msgs/ImageFlow). Fit: Huber IRLS started from
// a least-median-of-squares fit of minimal samples, scale from the median
// absolute residual; tracks
// with a residual beyond outlier_sigmas scales are outliers; the inliers are
// then fitted by least squares and the covariance is sigma^2 (A^T A)^-1 with
// sigma^2 = sum r^2 / (2 m - 6), floored at min_sigma^2.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace hapi_frontend {

struct AffineFitSettings {
  double huber_k = 1.345;        // [scales]
  double outlier_sigmas = 4.0;   // [scales]
  double min_sigma = 0.005;      // [px]
  int min_inliers = 10;
};

struct AffineFlowFit {
  bool ok = false;  // false: fewer than min_inliers inliers, or points that do not span the plane
  Eigen::Matrix<double, 6, 1> affine = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  int inliers = 0;
  double sigma = 0;         // [px] residual sigma per component (floored)
  std::vector<bool> inlier; // per input track
};

// from[i]: position in the earlier frame [px]; displacement[i]: to - from.
AffineFlowFit fitAffineFlow(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& displacement,
                            const Eigen::Vector2d& centre, const AffineFitSettings& settings);

}  // namespace hapi_frontend
