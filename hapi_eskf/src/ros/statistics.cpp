// Counters, stage timings and the /diagnostics status of EskfNodelet
// (statistics.hpp says which thread calls what).
#include "hapi_eskf/ros/statistics.hpp"

#include <algorithm>
#include <cstdio>

namespace hapi_eskf {
namespace ros_glue {

NodeletStatistics::NodeletStatistics(bool use_imu) : use_imu_(use_imu), prev_time_(ros::WallTime::now()) {}

void NodeletStatistics::recordFrame(const IterationReport& report, int n_landmarks, std::size_t backend_memory) {
  std::lock_guard<std::mutex> lk(mu_);
  ++stages_.n;
  stages_.sum += report;
  n_landmarks_ = n_landmarks;
  backend_memory_ = backend_memory;
}

void NodeletStatistics::recordBackend(const std::string& name, std::size_t memory) {
  std::lock_guard<std::mutex> lk(mu_);
  backend_name_ = name;
  backend_memory_ = memory;
}

void NodeletStatistics::recordFilterError(const std::string& what) {
  std::lock_guard<std::mutex> lk(mu_);
  last_filter_error_ = what;
}

void NodeletStatistics::recordCalibration(const CalibrationEstimate& c) {
  std::lock_guard<std::mutex> lk(mu_);
  calibration_ = c;
}

void NodeletStatistics::recordImuNoise(const ImuNoiseDensity& n) {
  std::lock_guard<std::mutex> lk(mu_);
  imu_noise_ = n;
}

void NodeletStatistics::recordStop(const std::string& why) {
  std::lock_guard<std::mutex> lk(mu_);
  stopped_ = why;
}

void NodeletStatistics::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat, std::uint64_t frames_dropped,
                                 std::uint64_t input_resubscriptions) {
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-6, (now - prev_time_).toSec());
  prev_time_ = now;
  const std::uint64_t accepted = counters.frames_accepted, processed = counters.frames_processed,
                      dropped = frames_dropped, outputs = counters.outputs;
  std::uint64_t rejected = 0;
  for (const auto& r : counters.rejected) rejected += r.load();
  const double in_rate = (accepted - prev_accepted_) / dt, proc_rate = (processed - prev_processed_) / dt;
  const std::uint64_t new_rejected = rejected - prev_rejected_, new_dropped = dropped - prev_dropped_;
  const double out_rate = (outputs - prev_outputs_) / dt;
  prev_outputs_ = outputs;
  prev_accepted_ = accepted;
  prev_processed_ = processed;
  prev_rejected_ = rejected;
  prev_dropped_ = dropped;
  const std::uint64_t scene_moving = counters.frames_scene_moving, vision_led = counters.frames_vision_led,
                      awaiting = counters.frames_awaiting_imu;
  const std::uint64_t new_scene_moving = scene_moving - prev_scene_moving_, new_vision_led = vision_led - prev_vision_led_,
                      new_awaiting = awaiting - prev_awaiting_imu_;
  prev_scene_moving_ = scene_moving;
  prev_vision_led_ = vision_led;
  prev_awaiting_imu_ = awaiting;

  StageStats s;
  std::string backend, last_error, stopped;
  std::size_t memory;
  int landmarks;
  CalibrationEstimate calib;
  ImuNoiseDensity imu_noise;
  {
    std::lock_guard<std::mutex> lk(mu_);
    imu_noise = imu_noise_;
    s = stages_;
    stages_ = StageStats();
    backend = backend_name_;
    memory = backend_memory_;
    landmarks = n_landmarks_;
    calib = calibration_;
    last_error = last_filter_error_;
    stopped = stopped_;
  }
  // Most important first: a stopped filter, input problems, then the filter's own state.
  if (!stopped.empty())
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "filter stopped: %s", stopped.c_str());
  else if (new_rejected > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%llu input messages rejected in the last %.1f s",
                  static_cast<unsigned long long>(new_rejected), dt);
  else if (new_dropped > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%llu frames dropped (processing slower than input)",
                  static_cast<unsigned long long>(new_dropped));
  else if (new_scene_moving > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "scanned surface moving (IMU still, images moving) in %llu frames: tracking the camera relative "
                  "to the surface",
                  static_cast<unsigned long long>(new_scene_moving));
  else if (new_vision_led > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                  "IMU prediction and map fit disagreed in %llu frames: vision leads",
                  static_cast<unsigned long long>(new_vision_led));
  else if (new_awaiting > 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "aligning to gravity (collecting IMU samples)");
  else if (accepted == 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "waiting for landmarks");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");

  const double n = std::max(1, s.n);
  stat.add("input_rate_hz", in_rate);
  stat.add("processing_rate_hz", proc_rate);
  // odom/pose/TF outputs per second: the frame rate, or the IMU rate with ~use_imu.
  stat.add("output_rate_hz", out_rate);
  stat.add("frames_received", counters.frames_received.load());
  stat.add("frames_accepted", accepted);
  stat.add("frames_processed", processed);
  stat.add("frames_dropped", dropped);
  stat.add("frames_stale_after_reset", counters.frames_stale.load());
  // Once idle: accepted == processed + dropped + stale_after_reset + failed.
  stat.add("frames_failed", counters.frames_failed.load());
  stat.add("rejected_total", rejected);
  for (int r = 1; r < kRejectCount; ++r)
    stat.add(std::string("rejected_") + rejectName(static_cast<Reject>(r)), counters.rejected[r].load());
  // Input topics re-subscribed after a silence (~input_timeout).
  stat.add("input_resubscriptions", input_resubscriptions);
  stat.add("update_skips", counters.update_skips.load());
  stat.add("relocalisations", counters.relocalisations.load());
  stat.add("frames_relocalising", counters.frames_relocalising.load());
  stat.add("filter_errors", counters.filter_errors.load());
  stat.add("backend_faults", counters.backend_faults.load());
  stat.add("last_filter_error", last_error);
  stat.add("resets", counters.resets.load());
  stat.add("time_jumps", counters.time_jumps.load());
  // Image stamp to the frame's correction in the outputs, over the run [ms].
  const hapi_nodelet_kit::LatencyHistogram::Summary lat = latency_.summary();
  stat.add("latency_p50_ms", lat.p50 * 1e3);
  stat.add("latency_p99_ms", lat.p99 * 1e3);
  stat.add("latency_max_ms", lat.max * 1e3);
  stat.add("latency_frames", lat.count);
  stat.add("landmarks", landmarks);
  stat.add("backend", backend);
  stat.add("backend_memory_mib", memory / kBytesPerMiB);
  // Mean per-stage wall time over the frames of this period [ms].
  stat.add("frames_in_period", s.n);
  stat.add("t_predict_ms", s.sum.t_predict_ms / n);
  stat.add("t_association_ms", s.sum.t_association_ms / n);
  stat.add("t_update_ms", s.sum.t_update_ms / n);
  stat.add("t_removal_ms", s.sum.t_removal_ms / n);
  stat.add("t_addition_ms", s.sum.t_addition_ms / n);
  stat.add("t_total_ms", s.sum.t_total_ms / n);
  stat.add("measurements_per_frame", s.sum.n_measurements / n);
  stat.add("updated_per_frame", s.sum.n_updated / n);
  stat.add("gated_out_per_frame", s.sum.n_gated_out / n);
  stat.add("added_per_frame", s.sum.n_added / n);
  stat.add("removed_per_frame", s.sum.n_removed / n);
  stat.add("mean_nis", s.sum.mean_nis / n);
  if (use_imu_) {
    stat.add("imu_samples_used", counters.imu_used.load());
    stat.add("imu_samples_dropped", counters.imu_dropped.load());
    stat.add("imu_dropped_invalid", counters.imu_invalid.load());
    stat.add("imu_dropped_saturated", counters.imu_saturated.load());
    stat.add("imu_dropped_before_frames", counters.imu_before_frames.load());
    stat.add("imu_dropped_far_from_frames", counters.imu_far_from_frames.load());
    stat.add("imu_dropped_no_extrinsic", counters.imu_no_extrinsic.load());
    stat.add("imu_dropped_out_of_order", counters.imu_out_of_order.load());
    stat.add("imu_dropped_overflow", counters.imu_overflow.load());
    stat.add("imu_rejected_by_filter", counters.imu_rejected_by_filter.load());
    stat.add("imu_gaps", counters.imu_gaps.load());
    stat.add("imu_rate_outputs", counters.imu_outputs.load());
    stat.add("imu_rate_outputs_held", counters.imu_outputs_held.load());
    stat.add("frames_awaiting_imu", awaiting);
    stat.add("frames_vision_led", vision_led);
    stat.add("frames_scene_moving", scene_moving);
    stat.add("frames_still", counters.frames_still.load());
    stat.add("zero_velocity_fused", counters.zero_velocity_fused.load());
    stat.add("zero_velocity_rejected", counters.zero_velocity_rejected.load());
    // The in-situ white-noise densities per IMU axis (0: not measured, or
    // imu_noise_in_situ off); the prediction takes the larger of these and
    // gyro_noise_density / accel_noise_density.
    char buf[96];
    std::snprintf(buf, sizeof(buf), "%.3g %.3g %.3g", imu_noise.gyro.x(), imu_noise.gyro.y(), imu_noise.gyro.z());
    stat.add("imu_gyro_noise_density_in_situ", std::string(buf));
    std::snprintf(buf, sizeof(buf), "%.3g %.3g %.3g", imu_noise.accel.x(), imu_noise.accel.y(), imu_noise.accel.z());
    stat.add("imu_accel_noise_density_in_situ", std::string(buf));
  }
  addCalibration(stat, calib);
}

// The online calibration's estimates with their 1 sigma (docs/DESIGN.md
// "Online calibration"): the time offset, the rotation's change from the
// configured one (rotation vector, camera axes) and the translation.
void NodeletStatistics::addCalibration(diagnostic_updater::DiagnosticStatusWrapper& stat,
                                       const CalibrationEstimate& c) {
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  auto vec = [](const Vec3& v, double scale) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), "%.4f %.4f %.4f", v.x() * scale, v.y() * scale, v.z() * scale);
    return std::string(buf);
  };
  if (c.time_offset_valid) {
    stat.add("calib_time_offset_ms", c.time_offset * 1e3);
    stat.add("calib_time_offset_sigma_ms", c.time_offset_sigma * 1e3);
  }
  if (c.extrinsic_valid) {
    stat.add("calib_rotation_change_deg", vec(c.rotation_change, kDeg));
    stat.add("calib_rotation_sigma_deg", vec(c.rotation_sigma, kDeg));
    stat.add("calib_translation_m", vec(c.p_bc, 1.0));
    stat.add("calib_translation_sigma_mm", vec(c.p_bc_sigma, 1e3));
  }
}

}  // namespace ros_glue
}  // namespace hapi_eskf
