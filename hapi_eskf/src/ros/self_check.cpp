// SelfCheck (self_check.hpp).
#include "hapi_eskf/ros/self_check.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <hapi_nodelet_kit/sample_quantiles.hpp>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <utility>

namespace hapi_eskf {
namespace ros_glue {
namespace {

using diagnostic_msgs::DiagnosticStatus;

std::string format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof(buf), fmt, args);
  va_end(args);
  return buf;
}

// A check's value names its own level: the summary only shows the worst.
std::string levelName(unsigned char level) {
  return level == DiagnosticStatus::ERROR ? "ERROR" : level == DiagnosticStatus::WARN ? "WARN" : "OK";
}

}  // namespace

SelfCheck::SelfCheck(const NodeletParams& params, NodeletStatistics& stats) : params_(params), stats_(stats) {}

void SelfCheck::frameMeasured(int n) {
  std::lock_guard<std::mutex> lk(mu_);
  landmarks_.push_back(n);
}

std::string SelfCheck::dominantDropCause() const {
  const NodeletStatistics::Counters& c = stats_.counters;
  const std::pair<std::uint64_t, const char*> causes[] = {
      {c.imu_far_from_frames, "stamps far from the image stamps (clocks not synchronised)"},
      {c.imu_no_extrinsic,
       "no TF from the IMU frame to the camera frame (publish the camera-IMU transform or set ~T_cam_imu)"},
      {c.imu_invalid, "non-finite values or a second IMU frame_id"},
      {c.imu_saturated, "saturated (~imu_gyro_limit, ~imu_accel_limit)"},
      {c.imu_out_of_order, "stamps not increasing"},
      {c.imu_overflow, "buffer overflow (frames too late for ~imu_buffer_size)"},
      {c.imu_rejected_by_filter, "rejected by the filter (older than its state)"}};
  const auto* best = std::max_element(std::begin(causes), std::end(causes),
                                      [](const auto& a, const auto& b) { return a.first < b.first; });
  return best->first > 0 ? best->second : "none dropped";
}

SelfCheck::Level SelfCheck::clockCheck(const Delta& d) const {
  if (d.far > 0)
    return {DiagnosticStatus::ERROR,
            format("IMU stamps %.3f s from the image stamps (beyond ~imu_max_frame_offset %.2f s): images and IMU "
                   "not on one clock; stamp both from one clock (hardware sync, or the drivers' ROS time)",
                   stats_.imu_frame_offset.load(), params_.imu_max_frame_offset)};
  const CalibrationEstimate c = stats_.calibration();
  const double change = c.time_offset - params_.filter.imu_time_offset;
  if (c.time_offset_valid && std::fabs(change) > params_.check_max_time_offset_change)
    return {DiagnosticStatus::WARN,
            format("online time-offset estimate %.1f ms, %.1f ms from imu_time_offset %.1f ms (beyond %.1f ms, held "
                   "by its prior): images and IMU clocks offset more than configured; measure the offset (Kalibr "
                   "timeshift_cam_imu) and set imu_time_offset",
                   c.time_offset * 1e3, change * 1e3, params_.filter.imu_time_offset * 1e3,
                   params_.check_max_time_offset_change * 1e3)};
  return {DiagnosticStatus::OK, ""};
}

SelfCheck::Level SelfCheck::imuCheck(const Delta& d, double dt) const {
  if (!params_.usesImu() || d.accepted == 0) return {DiagnosticStatus::OK, ""};
  if (d.received == 0)
    return {DiagnosticStatus::ERROR,
            format("no IMU samples on '%s' in the last %.1f s while landmarks arrive: IMU not fused; check the IMU "
                   "driver and the imu_topic remap",
                   params_.imu_topic.c_str(), dt)};
  const double unused = static_cast<double>(d.dropped) / static_cast<double>(d.received);
  if (unused > params_.check_max_imu_unused)
    return {DiagnosticStatus::ERROR,
            format("%.0f %% of the IMU samples received in %.1f s dropped: IMU not fused; most: %s", unused * 100, dt,
                   dominantDropCause().c_str())};
  return {DiagnosticStatus::OK, ""};
}

SelfCheck::Level SelfCheck::initialisationCheck(ros::WallTime now) const {
  if (stats_.counters.frames_processed > 0) return {DiagnosticStatus::OK, ""};
  const NodeletStatistics::Counters& c = stats_.counters;
  const bool have_frames = c.frames_accepted > 0;
  const double waited = (now - (have_frames ? first_frame_time_ : start_)).toSec();
  std::string why;
  if (!have_frames)
    why = "no landmarks received (front end not running, or the landmarks topic not remapped)";
  else if (c.frames_awaiting_imu > 0)
    why = format("the gravity alignment waits for IMU samples (%llu used, %llu dropped: %s)",
                 static_cast<unsigned long long>(c.imu_used.load()),
                 static_cast<unsigned long long>(c.imu_dropped.load()), dominantDropCause().c_str());
  else
    why = "frames received but none processed (see the filter status)";
  const unsigned char level = waited > params_.check_init_timeout ? DiagnosticStatus::ERROR : DiagnosticStatus::OK;
  return {level, format("not tracking after %.1f s: %s", waited, why.c_str())};
}

SelfCheck::Level SelfCheck::landmarksCheck(double median_landmarks) const {
  if (!(median_landmarks < params_.check_min_landmarks)) return {DiagnosticStatus::OK, ""};
  return {DiagnosticStatus::WARN,
          format("%.0f landmarks per frame reach the filter (< %d): too few to track; low texture (see the front "
                 "end's self-check)",
                 median_landmarks, params_.check_min_landmarks)};
}

void SelfCheck::produce(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-6, (now - prev_time_).toSec());
  prev_time_ = now;
  const NodeletStatistics::Counters& c = stats_.counters;
  const Delta total{c.frames_accepted, c.imu_received, c.imu_dropped - c.imu_before_frames, c.imu_far_from_frames};
  if (total.accepted > 0 && first_frame_time_.isZero()) first_frame_time_ = now;
  const Delta d{total.accepted - prev_.accepted, total.received - prev_.received, total.dropped - prev_.dropped,
                total.far - prev_.far};
  prev_ = total;
  std::vector<double> landmarks;
  {
    std::lock_guard<std::mutex> lk(mu_);
    landmarks.swap(landmarks_);
  }
  // The upper neighbour of the median for an even count.
  const double median_landmarks = hapi_nodelet_kit::quantileRoundedPosition(landmarks, 0.5, std::nan(""));

  stat.add("landmarks per frame median", median_landmarks);
  stat.add("imu samples received in period", d.received);
  stat.add("imu samples dropped in period", d.dropped);
  // The summary: the most severe failed check, the first of equals in the
  // order below (a clock problem explains the IMU's and the start's).
  const std::pair<const char*, Level> checks[] = {{"check.clock", clockCheck(d)},
                                                  {"check.imu", imuCheck(d, dt)},
                                                  {"check.initialisation", initialisationCheck(now)},
                                                  {"check.landmarks", landmarksCheck(median_landmarks)}};
  unsigned char worst = DiagnosticStatus::OK;
  std::string summary = stats_.counters.frames_processed > 0 ? "tracking" : "initialising";
  for (const auto& [key, r] : checks) {
    stat.add(key, r.message.empty() ? std::string("ok") : levelName(r.level) + ": " + r.message);
    if (r.level > worst) {
      worst = r.level;
      summary = r.message;
    }
  }
  stat.summary(worst, summary);
}

}  // namespace ros_glue
}  // namespace hapi_eskf
