// IMU sample checks, extrinsic lookup and buffer of EskfNodelet (imu_input.hpp
// says which thread calls what).
#include "hapi_eskf/ros/imu_input.hpp"

#include "hapi_eskf/ros/conversions.hpp"

#include <ros/console.h>
#include <tf2_eigen/tf2_eigen.h>

#include <cmath>
#include <cstdint>
#include <utility>

namespace hapi_eskf {
namespace ros_glue {

ImuInput::ImuInput(const NodeletParams& params, const tf2_ros::Buffer& tf, NodeletStatistics& stats,
                   std::string log_name)
    : params_(params),
      tf_(tf),
      stats_(stats),
      log_name_(std::move(log_name)),
      camera_frame_(params.camera_frame),
      stamp_guard_(params.time_jump_reset) {}

void ImuInput::onLandmarks(const std::string& camera_frame, double stamp) {
  std::lock_guard<std::mutex> lk(mu_);
  camera_frame_ = camera_frame;
  newest_frame_stamp_ = stamp;
  have_frame_stamp_ = true;
}

// Each reason has its own counter and its own rate-limited message (one
// throttled call site per reason, so one cannot hide another).
void ImuInput::count(NodeletStatistics::Counter& reason) {
  ++reason;
  ++stats_.counters.imu_dropped;
}

std::optional<TimedImuSample> ImuInput::accept(const sensor_msgs::Imu& msg) {
  NodeletStatistics::Counters& c = stats_.counters;
  Vec3 w, f;
  tf2::fromMsg(msg.angular_velocity, w);
  tf2::fromMsg(msg.linear_acceleration, f);
  const double stamp = msg.header.stamp.toSec();
  ++c.imu_received;
  if (!w.allFinite() || !f.allFinite() || !std::isfinite(stamp)) {
    count(c.imu_invalid);
    ROS_ERROR_THROTTLE_NAMED(2.0, log_name_,
                             "dropping IMU sample with a non-finite angular velocity, acceleration or stamp");
    return std::nullopt;
  }
  if (w.cwiseAbs().maxCoeff() >= params_.imu_gyro_limit || f.cwiseAbs().maxCoeff() >= params_.imu_accel_limit) {
    count(c.imu_saturated);
    ROS_ERROR_THROTTLE_NAMED(2.0, log_name_,
                             "dropping saturated IMU sample (largest rate %.1f rad/s, largest specific force %.1f "
                             "m/s^2; limits ~imu_gyro_limit, ~imu_accel_limit)",
                             w.cwiseAbs().maxCoeff(), f.cwiseAbs().maxCoeff());
    return std::nullopt;
  }
  const ImuSample sample = imuSampleOnCameraClock(stamp, w, f, params_.filter);
  std::lock_guard<std::mutex> lk(mu_);
  if (camera_frame_.empty() || !have_frame_stamp_) {  // nothing to relate the sample to before the first frame
    count(c.imu_before_frames);
    return std::nullopt;
  }
  if (std::abs(sample.stamp - newest_frame_stamp_) > params_.imu_max_frame_offset) {
    count(c.imu_far_from_frames);
    stats_.imu_frame_offset = sample.stamp - newest_frame_stamp_;
    ROS_ERROR_THROTTLE_NAMED(2.0, log_name_,
                             "dropping IMU sample at %.3f s: %.3f s from the newest image stamp "
                             "(~imu_max_frame_offset; clocks not synchronised?)",
                             sample.stamp, sample.stamp - newest_frame_stamp_);
    return std::nullopt;
  }
  const std::string& frame = msg.header.frame_id;
  if (!extrinsic_) {
    CameraExtrinsic from_param;
    std::string unused;
    if (!params_.T_cam_imu.empty() && cameraInImuFromKalibr(params_.T_cam_imu, &from_param, &unused)) {
      extrinsic_ = from_param;  // ~T_cam_imu: the calibration given as a parameter
    } else if (frame.empty() || frame == camera_frame_) {
      extrinsic_ = CameraExtrinsic();
    } else {
      // Static mounting assumed: looked up once, non-blocking.
      try {
        const Eigen::Isometry3d T_imu_cam =
            toIsometry(tf_.lookupTransform(frame, camera_frame_, ros::Time(0)).transform);
        CameraExtrinsic e;
        e.R_imu_cam = T_imu_cam.linear();
        e.p_imu_cam = T_imu_cam.translation();
        extrinsic_ = e;
      } catch (const tf2::TransformException& e) {
        count(c.imu_no_extrinsic);
        ROS_ERROR_THROTTLE_NAMED(2.0, log_name_, "no TF %s <- %s (the camera in the IMU frame), IMU sample dropped: %s",
                                 frame.c_str(), camera_frame_.c_str(), e.what());
        return std::nullopt;
      }
    }
    imu_frame_ = frame;
  } else if (frame != imu_frame_) {
    count(c.imu_invalid);
    ROS_ERROR_THROTTLE_NAMED(2.0, log_name_, "IMU sample in frame '%s', but the IMU is '%s': one IMU only (dropped)",
                             frame.c_str(), imu_frame_.c_str());
    return std::nullopt;
  }
  const hapi_nodelet_kit::StampCheck sc = stamp_guard_.check(static_cast<std::int64_t>(msg.header.stamp.toNSec()));
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) {
    // The buffer is kept in stamp order (the propagation relies on it).
    count(c.imu_out_of_order);
    ROS_WARN_THROTTLE_NAMED(2.0, log_name_, "IMU sample at %.6f not newer than the previous one (%.6f): dropped",
                            stamp, sc.previousSec());
    return std::nullopt;
  }
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset)
    buffer_.clear();  // samples of the old timeline would never be consumed
  TimedImuSample t{sample, msg.header.stamp - ros::Duration(params_.filter.imu_time_offset)};
  if (!buffer_.empty() && sample.stamp - buffer_.back().sample.stamp > params_.imu_max_gap) {
    ++c.imu_gaps;
    ROS_WARN_THROTTLE_NAMED(2.0, log_name_, "IMU gap of %.3f s before %.3f s (~imu_max_gap): the last sample is held",
                            sample.stamp - buffer_.back().sample.stamp, sample.stamp);
  }
  buffer_.push_back(t);
  while (static_cast<int>(buffer_.size()) > params_.imu_buffer_size) {
    buffer_.pop_front();
    count(c.imu_overflow);
  }
  return t;
}

std::vector<TimedImuSample> ImuInput::takeUpTo(double stamp) {
  std::vector<TimedImuSample> out;
  std::lock_guard<std::mutex> lk(mu_);
  while (!buffer_.empty() && buffer_.front().sample.stamp <= stamp) {
    out.push_back(buffer_.front());
    buffer_.pop_front();
  }
  return out;
}

void ImuInput::dropUpTo(double stamp) {
  std::lock_guard<std::mutex> lk(mu_);
  while (!buffer_.empty() && buffer_.front().sample.stamp <= stamp) buffer_.pop_front();
}

std::vector<TimedImuSample> ImuInput::samplesAfter(double stamp) const {
  std::vector<TimedImuSample> out;
  std::lock_guard<std::mutex> lk(mu_);
  for (const TimedImuSample& s : buffer_)
    if (s.sample.stamp > stamp) out.push_back(s);
  return out;
}

void ImuInput::clear() {
  std::lock_guard<std::mutex> lk(mu_);
  buffer_.clear();
}

std::optional<CameraExtrinsic> ImuInput::extrinsic() const {
  std::lock_guard<std::mutex> lk(mu_);
  return extrinsic_;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
