// IMU input of hapi_eskf/EskfNodelet (~motion_model gyro or inertial): checks
// each sensor_msgs/Imu sample (finite, not saturated, near the image clock,
// in stamp order), takes the camera-IMU extrinsic from ~T_cam_imu or else
// looks it up in TF once (static mounting), moves the stamp to the camera clock (EskfSettings
// imu_time_offset) and keeps the samples in strictly increasing stamp order
// until the worker consumes them for the filter's prediction. Every drop is
// counted and reported (rate-limited) with its reason; nothing malformed
// reaches the filter. Stamp order is the landmarks input's rule
// (hapi_nodelet_kit::StampGuard with ~time_jump_reset): a sample not after
// the previous one is dropped, a jump back beyond ~time_jump_reset starts a
// new timeline.
//
// Threads: the IMU callback calls accept(); the landmarks callback tells the
// camera frame and the newest image stamp; the worker takes, drops and reads
// samples and the extrinsic. mu_ guards everything else (the guard owns its
// lock, taken inside mu_).
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/statistics.hpp"
#include "hapi_eskf/types.hpp"

#include <hapi_nodelet_kit/stamp_guard.hpp>
#include <ros/time.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/buffer.h>

#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

// A sample as the filter takes it, with its exact output stamp.
struct TimedImuSample {
  ImuSample sample;     // IMU frame, stamp on the camera clock [s]
  ros::Time ros_stamp;  // the same instant as a ros::Time, for output headers
};

class ImuInput {
 public:
  // `tf` must outlive this object; `log_name` is the nodelet's logger name.
  ImuInput(const NodeletParams& params, const tf2_ros::Buffer& tf, NodeletStatistics& stats, std::string log_name);

  // --- landmarks callback: the camera frame (fixed by ~camera_frame or the
  // first accepted landmarks message; samples before it are dropped) and
  // the newest image stamp.
  void onLandmarks(const std::string& camera_frame, double stamp);

  // --- IMU callback: the sample, on the camera clock and buffered; empty
  // when it was dropped (counted): non-finite, saturated, far from the image
  // clock, before the camera frame is known, from a second IMU frame, not
  // newer than the previous one, or no extrinsic in TF yet. A stamp jumping
  // back by more than ~time_jump_reset starts a new timeline: the buffer is
  // cleared (the old samples would never be consumed).
  std::optional<TimedImuSample> accept(const sensor_msgs::Imu& msg);

  // --- worker thread ---
  std::vector<TimedImuSample> takeUpTo(double stamp);         // removed from the buffer
  void dropUpTo(double stamp);                                // samples the filter no longer needs
  std::vector<TimedImuSample> samplesAfter(double stamp) const;  // left in the buffer
  void clear();                                               // filter reset
  // The camera in the IMU frame, once TF gave it.
  std::optional<CameraExtrinsic> extrinsic() const;

 private:
  void count(NodeletStatistics::Counter& reason);  // a drop, by reason

  const NodeletParams params_;
  const tf2_ros::Buffer& tf_;
  NodeletStatistics& stats_;
  const std::string log_name_;

  mutable std::mutex mu_;
  std::string camera_frame_;
  double newest_frame_stamp_ = 0.0;
  bool have_frame_stamp_ = false;
  hapi_nodelet_kit::StampGuard stamp_guard_;
  std::string imu_frame_;  // the frame of the first sample; set with the extrinsic
  std::optional<CameraExtrinsic> extrinsic_;
  std::deque<TimedImuSample> buffer_;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
