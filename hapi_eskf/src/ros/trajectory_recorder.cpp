// ~path and ~save_trajectory of EskfNodelet (trajectory_recorder.hpp says
// which thread calls what).
#include "hapi_eskf/ros/trajectory_recorder.hpp"

#include "hapi_eskf/ros/conversions.hpp"

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Path.h>
#include <ros/console.h>

#include <utility>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

TrajectoryRecorder::TrajectoryRecorder(const NodeletParams& params, ros::Publisher path_pub, std::string log_name)
    : world_frame_(params.world_frame),
      output_dir_(params.output_dir),
      max_length_(params.path_max_length),
      log_name_(std::move(log_name)),
      path_pub_(std::move(path_pub)) {}

void TrajectoryRecorder::record(const ros::Time& stamp, const CameraInMap& T_map_cam) {
  StampedPose sp;
  sp.stamp = stamp.toSec();
  sp.p = T_map_cam.p;
  sp.q = T_map_cam.q;
  nav_msgs::Path path;
  const bool want_path = path_pub_.getNumSubscribers() > 0;
  {
    std::lock_guard<std::mutex> lk(mu_);
    trajectory_.push_back(sp);
    while (static_cast<int>(trajectory_.size()) > max_length_) trajectory_.pop_front();
    if (want_path) {
      path.poses.reserve(trajectory_.size());
      for (const StampedPose& s : trajectory_) {
        geometry_msgs::PoseStamped p;
        p.header.stamp = ros::Time(s.stamp);
        p.header.frame_id = world_frame_;
        p.pose = toPoseMsg(s.p, s.q);
        path.poses.push_back(p);
      }
    }
  }
  if (want_path) {
    path.header.stamp = stamp;
    path.header.frame_id = world_frame_;
    path_pub_.publish(path);
  }
}

void TrajectoryRecorder::clear(const ros::Time& stamp) {
  {
    std::lock_guard<std::mutex> lk(mu_);
    trajectory_.clear();
  }
  nav_msgs::Path empty;
  empty.header.frame_id = world_frame_;
  empty.header.stamp = stamp;
  path_pub_.publish(empty);
}

bool TrajectoryRecorder::save(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::vector<StampedPose> poses;
  {
    std::lock_guard<std::mutex> lk(mu_);
    poses.assign(trajectory_.begin(), trajectory_.end());
  }
  const std::string path = timestampedPath(output_dir_, "hapi_trajectory", "tum");
  const std::string err = writeTum(path, poses);
  res.success = err.empty();
  res.message = res.success ? path : err;
  if (res.success)
    ROS_INFO_NAMED(log_name_, "saved %zu poses (TUM) to %s", poses.size(), path.c_str());
  else
    ROS_ERROR_NAMED(log_name_, "~save_trajectory failed: %s", err.c_str());
  return true;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
