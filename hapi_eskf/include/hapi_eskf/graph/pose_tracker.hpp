// Pose tracking between window solves (docs/DESIGN.md "Graph SLAM", tracking):
// a pose-only Gauss-Newton solve of one frame's observations of known
// landmarks, the landmarks held at their current estimates and their
// covariance added to each measurement's, with the robust loss of the
// settings as iteratively reweighted least squares. Cheap (6 unknowns), so
// the frame thread runs it every frame without waiting for the window solver.
#pragma once

#include "hapi_eskf/graph/graph_settings.hpp"
#include "hapi_eskf/types.hpp"

#include <vector>

namespace hapi_eskf {
namespace graph {

struct TrackedPoint {
  Vec3 m = Vec3::Zero();         // landmark, world [m]
  Mat3 Cm = Mat3::Zero();        // its covariance
  Vec3 z = Vec3::Zero();         // measurement, camera frame
  Mat3 Cz = Mat3::Identity();
};

// The IRLS weight rho'(s) of the robust loss at s = |r|^2 (whitened), the
// same functions Ceres uses for the graph (bundle_adjustment.cpp).
double robustWeight(const GraphSettings& settings, double s);

// Gauss-Newton from `predicted`; on success *pose is the solution and *C its
// covariance [dp world, dtheta local] ((J^T W J)^-1 at the solution).
// False (outputs untouched) with fewer than 3 points or singular normal
// equations.
bool trackPose(const std::vector<TrackedPoint>& points, const PoseState& predicted, const GraphSettings& settings,
               PoseState* pose, Mat6* C);

}  // namespace graph
}  // namespace hapi_eskf
