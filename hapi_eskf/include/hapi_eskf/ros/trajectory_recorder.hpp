// Trajectory of hapi_eskf/EskfNodelet: the pose of every processed frame in
// world_frame (bounded by ~path_max_length), published as ~path
// (nav_msgs/Path, latched) and written by ~save_trajectory as a TUM file.
//
// Threads: the worker records and clears; the ~save_trajectory service reads.
// mu_ guards the trajectory.
#pragma once

#include "hapi_eskf/ros/conversions.hpp"
#include "hapi_eskf/ros/export.hpp"
#include "hapi_eskf/ros/params.hpp"

#include <ros/publisher.h>
#include <ros/time.h>
#include <std_srvs/Trigger.h>

#include <deque>
#include <mutex>
#include <string>

namespace hapi_eskf {
namespace ros_glue {

class TrajectoryRecorder {
 public:
  // `log_name` is the nodelet's logger name.
  TrajectoryRecorder(const NodeletParams& params, ros::Publisher path_pub, std::string log_name);

  // --- worker thread ---
  // The pose of a processed frame; ~path is published when subscribed.
  void record(const ros::Time& stamp, const CameraInMap& T_map_cam);
  // Filter reset: forgets the trajectory and publishes an empty path.
  void clear(const ros::Time& stamp);

  // --- ~save_trajectory service: TUM file in ~output_dir ---
  bool save(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);

 private:
  const std::string world_frame_, output_dir_;
  const int max_length_;
  const std::string log_name_;
  ros::Publisher path_pub_;

  std::mutex mu_;
  std::deque<StampedPose> trajectory_;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
