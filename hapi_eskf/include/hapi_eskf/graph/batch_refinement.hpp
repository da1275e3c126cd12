// Full batch refinement of a factor graph (docs/DESIGN.md "Graph SLAM",
// batch): every keyframe but the first (the gauge) and every landmark free,
// re-linearised by Levenberg-Marquardt from the current estimates until
// convergence, then the refined map (PLY) and trajectory (TUM) written in
// the formats of map_files.hpp. Works on a copy (GraphSlam::snapshot(), or
// a graph built from a recorded ES-EKF run), so a live back end carries on.
#pragma once

#include "hapi_eskf/graph/bundle_adjustment.hpp"
#include "hapi_eskf/graph/graph_map.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"
#include "hapi_eskf/status.hpp"

#include <string>

namespace hapi_eskf {
namespace graph {

// Refines *map in place; landmark covariances become the conditional
// approximation (graph_map.hpp) at the solution.
Status refineBatch(const GraphSettings& settings, GraphMap* map, BundleReport* report);

// Writes the landmarks to `ply_path` and the trajectory to `tum_path` (every
// recorded frame through its keyframe; the keyframes when no frame was
// recorded). "" on success, else the error.
std::string writeGraphFiles(const GraphMap& map, const std::string& ply_path, const std::string& tum_path);

}  // namespace graph
}  // namespace hapi_eskf
