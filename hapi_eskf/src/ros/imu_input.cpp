// IMU sample checks, mounting rotation and buffer of EskfNodelet (imu_input.hpp
// says which thread calls what).
#include "hapi_eskf/ros/imu_input.hpp"

#include "hapi_eskf/ros/conversions.hpp"

#include <ros/console.h>

#include <cmath>
#include <cstdint>
#include <utility>

namespace hapi_eskf {
namespace ros_glue {

ImuInput::ImuInput(const NodeletParams& params, const tf2_ros::Buffer& tf, NodeletStatistics& stats,
                   std::string log_name)
    : buffer_size_(params.imu_buffer_size),
      tf_(tf),
      stats_(stats),
      log_name_(std::move(log_name)),
      camera_frame_(params.camera_frame),
      stamp_guard_(params.time_jump_reset) {}

void ImuInput::setCameraFrame(const std::string& camera_frame) {
  std::lock_guard<std::mutex> lk(mu_);
  camera_frame_ = camera_frame;
}

std::optional<ImuSample> ImuInput::accept(const sensor_msgs::Imu& msg) {
  const Vec3 g(msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z);
  const double stamp = msg.header.stamp.toSec();
  if (!g.allFinite() || !std::isfinite(stamp)) {
    ++stats_.counters.imu_dropped;
    ROS_ERROR_THROTTLE_NAMED(1.0, log_name_, "dropping IMU sample with non-finite angular velocity or stamp");
    return std::nullopt;
  }
  std::lock_guard<std::mutex> lk(mu_);
  if (camera_frame_.empty()) {  // the camera frame is not known before the first landmarks message
    ++stats_.counters.imu_dropped;
    return std::nullopt;
  }
  const hapi_nodelet_kit::StampCheck sc = stamp_guard_.check(static_cast<std::int64_t>(msg.header.stamp.toNSec()));
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReject) {
    // The buffer is kept in stamp order (the propagation relies on it).
    ++stats_.counters.imu_dropped;
    ROS_WARN_THROTTLE_NAMED(2.0, log_name_, "IMU sample at %.6f not newer than the previous one (%.6f): dropped",
                            stamp, sc.previousSec());
    return std::nullopt;
  }
  if (sc.verdict == hapi_nodelet_kit::StampVerdict::kReset)
    buffer_.clear();  // samples of the old timeline would never be consumed
  const std::string& f = msg.header.frame_id;
  auto it = imu_to_camera_.find(f);
  if (it == imu_to_camera_.end()) {
    if (f.empty() || f == camera_frame_) {
      it = imu_to_camera_.emplace(f, Eigen::Quaterniond::Identity()).first;
    } else {
      // Static mounting assumed: the rotation is looked up once, non-blocking.
      try {
        const auto t = tf_.lookupTransform(camera_frame_, f, ros::Time(0));
        it = imu_to_camera_.emplace(f, Eigen::Quaterniond(toIsometry(t.transform).linear())).first;
      } catch (const tf2::TransformException& e) {
        ++stats_.counters.imu_dropped;
        ROS_WARN_THROTTLE_NAMED(2.0, log_name_, "no TF %s <- %s yet, IMU sample dropped: %s", camera_frame_.c_str(),
                                f.c_str(), e.what());
        return std::nullopt;
      }
    }
  }
  const ImuSample sample{stamp, msg.header.stamp, it->second * g};
  buffer_.push_back(sample);
  while (static_cast<int>(buffer_.size()) > buffer_size_) {
    buffer_.pop_front();
    ++stats_.counters.imu_dropped;
  }
  return sample;
}

std::vector<ImuSample> ImuInput::takeUpTo(double stamp) {
  std::vector<ImuSample> out;
  std::lock_guard<std::mutex> lk(mu_);
  while (!buffer_.empty() && buffer_.front().stamp <= stamp) {
    out.push_back(buffer_.front());
    buffer_.pop_front();
  }
  return out;
}

void ImuInput::dropUpTo(double stamp) {
  std::lock_guard<std::mutex> lk(mu_);
  while (!buffer_.empty() && buffer_.front().stamp <= stamp) buffer_.pop_front();
}

std::vector<ImuSample> ImuInput::samplesAfter(double stamp) const {
  std::vector<ImuSample> out;
  std::lock_guard<std::mutex> lk(mu_);
  for (const ImuSample& s : buffer_)
    if (s.stamp > stamp) out.push_back(s);
  return out;
}

void ImuInput::clear() {
  std::lock_guard<std::mutex> lk(mu_);
  buffer_.clear();
}

}  // namespace ros_glue
}  // namespace hapi_eskf
