// Marginal covariances of a bundle problem at its current parameters
// (docs/DESIGN.md "Graph SLAM", covariances): blocks of the inverse of the
// Gauss-Newton information H = J^T J, J the Jacobian in the tangent spaces
// with the robust loss's correction (what ceres::Covariance inverts). Each
// residual touches at most one point, so H = [D B^T; B A] with D the points'
// 3x3 blocks, and the blocks come from the Schur complement on the poses:
//   Sigma_poses = S^-1,  S = A - B D^-1 B^T,
//   Sigma_i = D_i^-1 + D_i^-1 B_i^T S^-1 B_i D_i^-1   (point i, B_i its columns).
// ceres::Covariance (sparse QR) gives the same blocks up to round-off, but
// back-substitutes once per requested column through the whole problem's R;
// here the cost is one dense inverse of the poses' 6n x 6n S and sums over the
// observations.
#pragma once

#include "hapi_eskf/types.hpp"

#include <vector>

namespace ceres {
class Problem;
}

namespace hapi_eskf {
namespace graph {

// `points`: 3-vector parameter blocks without a manifold; `poses`: blocks
// whose tangent space has 6 dimensions. Every other parameter block of the
// problem is held constant. Outputs, in the order of the inputs: the points'
// covariances and the poses' in their tangent spaces. False (outputs
// unspecified) when a residual couples two points or the information is
// singular (a point or the poses not determined).
bool marginalCovariances(ceres::Problem* problem, const std::vector<double*>& points,
                         const std::vector<double*>& poses, std::vector<Mat3>* point_cov,
                         std::vector<Mat6>* pose_cov_tangent);

}  // namespace graph
}  // namespace hapi_eskf
