// Ceres least squares over (part of) the factor graph (docs/DESIGN.md "Graph
// SLAM"): every observation is a stereo point residual whitened by its
// covariance, r = L^-1 (z - R^T (m - p)) with L L^T = Cz, under the robust
// loss of the settings. Keyframes flagged constant stay where they are (the
// gauge, and the old keyframes outside the online window); every landmark
// that one of the given observations touches is free. The online window
// solver and the full batch refinement both call this.
#pragma once

#include "hapi_eskf/graph/graph_map.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"
#include "hapi_eskf/status.hpp"

#include <vector>

namespace hapi_eskf {
namespace graph {

struct BundleOptions {
  int max_iterations = 10;
  bool sparse = false;          // sparse Schur (large batch) instead of dense Schur (window)
  // Landmark and free keyframe marginal covariances (marginal_covariance.hpp), with every
  // constant keyframe that has a covariance acting as a prior of it (not as
  // an exact pose): the window's marginals then carry the older map's
  // uncertainty (docs/DESIGN.md "Graph SLAM", covariances).
  bool covariances = false;
};

struct BundleReport {
  int iterations = 0;
  int residuals = 0;
  double initial_cost = 0.0, final_cost = 0.0;  // 0.5 sum rho(|r|^2)
  bool usable = false;             // Ceres returned a usable solution (the map was written)
  bool covariance_ok = false;      // ceres::Covariance succeeded (else the conditional approximation)
  Mat6 newest_pose_covariance = Mat6::Zero();  // [dp world, dtheta local] of the newest free keyframe
};

// Solves over map->observations; keyframe k is constant when constant[k].
// Writes the solution (poses, landmark positions and covariances, free
// keyframes' covariances with options.covariances) back into
// *map only when Ceres reports it usable. kInvalidArgument on a size
// mismatch, kEmptyInput without observations.
Status adjustBundle(const GraphSettings& settings, const BundleOptions& options, const std::vector<char>& constant,
                    GraphMap* map, BundleReport* report);

}  // namespace graph
}  // namespace hapi_eskf
