// A robust plane fit n . X = c to 3D points (docs/DESIGN.md "Surface
// motion", depth): a least-median-of-squares start (its inliers fitted),
// then iteratively reweighted least squares
// with Huber weights on the point-to-plane residuals, the scale from their
// median absolute deviation. Its covariance is the weighted least-squares
// one, in a tangent parametrisation of the normal.
#pragma once

#include "hapi_eskf/types.hpp"

#include <vector>

namespace hapi_eskf {
namespace surface_motion {

struct PlaneFit {
  bool ok = false;         // false: fewer than 3 points or degenerate (collinear) points
  Vec3 normal = Vec3::UnitZ();
  double offset = 0;       // c [m]
  // The normal moves as n + a t1 + b t2 (t1, t2 a basis of its plane);
  // covariance of (a, b, c) [1, 1, m^2].
  Vec3 t1 = Vec3::UnitX(), t2 = Vec3::UnitY();
  Mat3 covariance = Mat3::Zero();
  double sigma = 0;        // [m] residual scale used for the covariance
  int inliers = 0;         // residuals within the Huber threshold at the end
};

PlaneFit fitPlane(const std::vector<Vec3>& points, double huber_k, int iterations, double sigma_floor);

}  // namespace surface_motion
}  // namespace hapi_eskf
