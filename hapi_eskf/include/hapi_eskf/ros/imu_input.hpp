// IMU input of hapi_eskf/EskfNodelet (~use_imu): checks each sensor_msgs/Imu
// sample, rotates its angular velocity into the camera frame (the IMU
// mounting rotation is looked up in TF once per IMU frame_id and cached,
// static mounting assumed) and keeps the samples, in strictly increasing
// stamp order, until the worker consumes them for the filter's prediction.
// Stamp order is the landmarks input's rule (hapi_nodelet_kit::StampGuard
// with ~time_jump_reset): a sample not after the previous one is dropped, a
// jump back beyond ~time_jump_reset starts a new timeline.
//
// Threads: the IMU callback calls accept(); the landmarks callback tells the
// camera frame once it is known; the worker takes, drops and reads samples.
// mu_ guards everything else (the guard owns its lock, taken inside mu_).
#pragma once

#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/statistics.hpp"
#include "hapi_eskf/types.hpp"

#include <hapi_nodelet_kit/stamp_guard.hpp>
#include <ros/time.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>

#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

struct ImuSample {
  double stamp;
  ros::Time ros_stamp;  // exact, for the output header
  Vec3 gyro_camera;     // angular velocity in the camera frame [rad/s]
};

class ImuInput {
 public:
  // `tf` must outlive this object; `log_name` is the nodelet's logger name.
  ImuInput(const NodeletParams& params, const tf2_ros::Buffer& tf, NodeletStatistics& stats, std::string log_name);

  // --- landmarks callback: the camera frame, fixed by ~camera_frame or the
  // first accepted landmarks message; samples before it are dropped.
  void setCameraFrame(const std::string& camera_frame);

  // --- IMU callback: the sample, in the camera frame and buffered; empty when
  // it was dropped (counted in imu_dropped): non-finite, before the camera
  // frame is known, not newer than the previous one, or no mounting TF yet.
  // A stamp jumping back by more than ~time_jump_reset starts a new timeline:
  // the buffer is cleared (the old samples would never be consumed).
  std::optional<ImuSample> accept(const sensor_msgs::Imu& msg);

  // --- worker thread ---
  std::vector<ImuSample> takeUpTo(double stamp);         // removed from the buffer
  void dropUpTo(double stamp);                           // samples the filter no longer needs
  std::vector<ImuSample> samplesAfter(double stamp) const;  // left in the buffer
  void clear();                                          // filter reset

 private:
  const int buffer_size_;
  const tf2_ros::Buffer& tf_;
  NodeletStatistics& stats_;
  const std::string log_name_;

  mutable std::mutex mu_;
  std::string camera_frame_;
  hapi_nodelet_kit::StampGuard stamp_guard_;
  std::map<std::string, Eigen::Quaterniond> imu_to_camera_;  // cached static rotations
  std::deque<ImuSample> buffer_;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
