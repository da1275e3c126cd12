// Private (~) parameters of hapi_eskf/EskfNodelet, read and validated once at
// start-up. Every field is documented with its default in config/eskf.yaml.
#pragma once

#include "hapi_eskf/settings.hpp"

#include <string>
#include <vector>

namespace ros {
class NodeHandle;
}

namespace hapi_eskf {
namespace ros_glue {

struct NodeletParams {
  EskfSettings filter;              // same names as the EskfSettings fields
  bool allow_cpu_fallback = true;   // backend=cuda but no usable device -> cpu (loud warning)

  // Frames (REP-105). The filter's world is the first camera pose; it is
  // published as `world_frame`. With `base_frame` set, map is anchored at the
  // first base pose instead (see docs in config/eskf.yaml) and TF is
  // world_frame -> base_frame, else world_frame -> camera frame.
  std::string world_frame = "map";
  std::string camera_frame;          // empty: the frame_id of the first accepted message
  std::string base_frame;            // empty: publish world_frame -> camera frame
  bool publish_tf = true;

  double map_publish_rate = 1.0;     // [Hz]
  int path_max_length = 10000;       // poses kept for ~path and ~save_trajectory
  int max_measurements_per_msg = 2000;
  double time_jump_reset = 1.0;      // [s] a stamp this far backwards resets the filter
  double diagnostics_period = 1.0;   // [s]

  bool use_imu = false;
  std::string imu_topic = "imu";       // sensor_msgs/Imu, gyro used for prediction
  double gyro_noise_density = 1.7e-4;  // [rad/s/sqrt(Hz)]
  int imu_buffer_size = 2000;          // samples waiting for the next frame

  std::string output_dir = "/tmp";   // ~save_map / ~save_trajectory write here

  // Set by loadParams: names under ~ that no parameter reads (typos such as
  // ~max_landmark would otherwise be silently ignored); the nodelet warns.
  std::vector<std::string> unknown;

  // Empty when valid, else a message naming the offending parameter.
  std::string validate() const;
};

// Reads every parameter from `pnh` (defaults above). Returns an empty string on
// success, else the error (wrong type, unknown backend name, out of range).
std::string loadParams(const ros::NodeHandle& pnh, NodeletParams* out);

}  // namespace ros_glue
}  // namespace hapi_eskf
