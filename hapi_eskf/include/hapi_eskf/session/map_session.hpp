// A session's map between the running back end and a map file
// (docs/DESIGN.md "Map file"): the pool as a map to save, whether the
// settings can take a map, and a read map put into a freshly reset back
// end. What hapi_eskf/EskfNodelet's ~save_map, ~load_map and ~map_file do,
// ROS-free.
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/map_file/map_data.hpp"
#include "hapi_eskf/map_file/map_error.hpp"
#include "hapi_eskf/settings.hpp"

#include <Eigen/Geometry>

namespace hapi_eskf {
namespace map_file {

// Why a map cannot be loaded with these settings (kBadValue naming the
// setting): only backend_algorithm eskf loads maps (the tested one; seif
// runs in the same filter but is not tested with a map), not with the inertial model (its
// gravity alignment empties the pool), only with RANSAC on (the fit that
// places the camera), and the map must leave max_new_landmarks free in the
// pool. Empty when it can.
MapError checkLoadable(const MapData& map, const EskfSettings& settings);

// The ES-EKF's pool as a map in the frame `T_out_world` maps the filter's
// world to (the published map frame: positions moved, covariances rotated).
// `header` gives everything but the landmarks (frames, calibration,
// creation time); the gravity direction is the filter's when its motion
// model estimates gravity, else none. kBadValue when `backend` is not an
// Eskf (eskf, seif) or its pool is empty; *skipped counts landmarks a reader would
// refuse (left out).
MapError mapFromBackend(const SlamBackend& backend, const Eigen::Isometry3d& T_out_world, const MapData& header,
                        MapData* out, int* skipped);

// Puts `map` into `backend` right after its reset (Eskf::loadMap):
// kBadValue naming the refusal; nothing is loaded then.
MapError loadIntoBackend(const MapData& map, SlamBackend* backend);

}  // namespace map_file
}  // namespace hapi_eskf
