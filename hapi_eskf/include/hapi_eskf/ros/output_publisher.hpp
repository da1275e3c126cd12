// Pose outputs of hapi_eskf/EskfNodelet: ~odom (nav_msgs/Odometry), ~pose
// (PoseWithCovarianceStamped) and TF world_frame -> camera (or base) frame,
// always with strictly increasing stamps. Owns the map anchoring (REP-105:
// T_map_world, identity unless ~base_frame) and, with an IMU motion model,
// the IMU-rate output: a copy of the pose block re-based on the filter after
// every frame and stepped by every newer IMU sample (pose_propagator.hpp), so
// outputs keep flowing at the IMU rate while the worker is busy with a frame.
//
// Threads: the worker (anchoring, per-frame output, filter reset) and the IMU
// callback (publishImuRate). mu_ guards everything.
#pragma once

#include "hapi_eskf/eskf/pose_propagator.hpp"
#include "hapi_eskf/ros/conversions.hpp"
#include "hapi_eskf/ros/imu_input.hpp"
#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/statistics.hpp"

#include <ros/publisher.h>
#include <ros/time.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>
#include <mutex>
#include <string>

namespace hapi_eskf {
namespace ros_glue {

class OutputPublisher {
 public:
  // `imu`: the IMU input with an IMU motion model (else null; must outlive
  // this object);
  // `log_name` is the nodelet's logger name.
  OutputPublisher(const NodeletParams& params, ros::Publisher odom_pub, ros::Publisher pose_pub,
                  const ImuInput* imu, NodeletStatistics& stats, std::string log_name);

  // --- worker thread ---
  // Anchoring of the published world frame, fixed at each filter start:
  // T_map_world = T_base_cam of the first frame with ~base_frame (so
  // T_cam_base is its inverse), else identity.
  void setMapAnchor(const Eigen::Isometry3d& T_map_world);
  // A loaded map (map_session.hpp) is the filter's world and already in the
  // published frame: T_map_world = identity; the base mounting
  // (T_cam_base from setMapAnchor) stays.
  void unanchorMap();
  Eigen::Isometry3d mapFromWorld() const;
  // After a processed frame: publishes its pose (unless the IMU-rate output
  // is already past it), re-bases the IMU-rate copy and catches up with the
  // samples already received. scene_moving: the frame's
  // IterationReport::scene_moving (the IMU-rate copy then follows the
  // surface, pose_propagator.hpp). Returns T_map_cam of the frame (for the path).
  CameraInMap publishFrame(const ros::Time& stamp, const std::string& camera_frame, const SlamBackend& filter,
                           bool scene_moving);
  // Filter reset: the new timeline may start earlier; the copy is void.
  void restart();

  // --- IMU callback (IMU motion model) ---
  // One step of the copy and its output.
  void publishImuRate(const TimedImuSample& s);

 private:
  void stepAndPublish(const TimedImuSample& s);  // under mu_
  void publish(const ros::Time& stamp, const PoseState& pose, const Mat12& C, const CameraInMap& T_map_cam);

  const std::string world_frame_, base_frame_;
  const bool publish_tf_;
  const ImuInput* const imu_;
  NodeletStatistics& stats_;
  const std::string log_name_;
  ros::Publisher odom_pub_, pose_pub_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  mutable std::mutex mu_;
  Eigen::Isometry3d T_map_world_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_cam_base_ = Eigen::Isometry3d::Identity();
  std::string camera_frame_;  // child frame: the camera frame of the last processed frame
  std::unique_ptr<PosePropagator> propagator_;  // IMU motion model only
  ros::Time last_output_stamp_;  // zero: none since the start
};

}  // namespace ros_glue
}  // namespace hapi_eskf
