// File export for ~save_map (PLY) and ~save_trajectory (TUM): the formats are
// the core's (hapi_eskf/map_files.hpp, shared with the ROS-free tools); the
// nodelet's code names them in its own namespace.
#pragma once

#include "hapi_eskf/backend/map_files.hpp"

namespace hapi_eskf {
namespace ros_glue {

using hapi_eskf::StampedPose;
using hapi_eskf::timestampedPath;
using hapi_eskf::writePly;
using hapi_eskf::writeTum;

}  // namespace ros_glue
}  // namespace hapi_eskf
