// Counters and per-stage timings of hapi_eskf/EskfNodelet, and the
// /diagnostics status built from them (keys listed in diagnose()).
//
// Threads: the counters are atomics, counted from any thread (callbacks,
// worker, IMU-rate output) without a lock. The worker records the filter's
// figures (recordFrame, recordBackend, recordFilterError); the diagnostics
// timer calls diagnose(). mu_ guards the filter's figures; the previous
// report's values are the diagnostics timer's own.
#pragma once

#include "hapi_eskf/eskf/calibration_block.hpp"
#include "hapi_eskf/ros/validation.hpp"
#include "hapi_eskf/types.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <hapi_nodelet_kit/latency_histogram.hpp>
#include <ros/time.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>

namespace hapi_eskf {
namespace ros_glue {

// Backend memory is reported in MiB.
constexpr double kBytesPerMiB = 1024.0 * 1024.0;

class NodeletStatistics {
 public:
  using Counter = std::atomic<std::uint64_t>;
  struct Counters {
    Counter frames_received{0}, frames_accepted{0}, frames_processed{0};
    Counter frames_stale{0};   // accepted before a reset: belonged to the old timeline
    Counter frames_failed{0};  // taken by the worker but not used (filter error, exception, no TF)
    Counter resets{0}, time_jumps{0}, update_skips{0}, filter_errors{0};
    Counter backend_faults{0};  // Status::kBackendError in a frame (a CUDA call failed)
    Counter relocalisations{0}, frames_relocalising{0};
    Counter imu_received{0}, imu_used{0}, imu_dropped{0};
    // Drops by reason (their sum is imu_dropped) and gaps (samples kept).
    Counter imu_invalid{0}, imu_saturated{0}, imu_before_frames{0}, imu_far_from_frames{0}, imu_no_extrinsic{0},
        imu_out_of_order{0}, imu_overflow{0}, imu_rejected_by_filter{0};
    Counter imu_gaps{0};
    Counter frames_awaiting_imu{0};  // inertial model not yet aligned to gravity
    Counter frames_vision_led{0}, frames_scene_moving{0};  // IMU and vision disagreed (scene_motion_monitor.hpp)
    // Still frames and their zero-velocity updates (eskf/zero_velocity_update.hpp).
    Counter frames_still{0}, zero_velocity_fused{0}, zero_velocity_rejected{0};
    Counter outputs{0};      // odom/pose/TF outputs (per frame, or per IMU sample with an IMU model)
    Counter imu_outputs{0};  // of which from the IMU-rate propagation
    Counter imu_outputs_held{0};  // IMU samples without output: velocity not yet measured (pose_propagator.hpp)
    std::array<Counter, kRejectCount> rejected{};  // by Reject reason
  };

  // `use_imu`: the IMU counters are reported only with an IMU motion model.
  explicit NodeletStatistics(bool use_imu);

  Counters counters;
  // The newest IMU sample's stamp minus the newest image stamp when a sample
  // was dropped as too far from the frames [s] (the self-check's number).
  std::atomic<double> imu_frame_offset{0.0};

  // --- worker thread ---
  // A frame the filter used: its stage timings and the pool after it.
  void recordFrame(const IterationReport& report, int n_landmarks, std::size_t backend_memory);
  void recordBackend(const std::string& name, std::size_t memory);
  void recordFilterError(const std::string& what);
  // The online calibration after a frame (calibration_block.hpp).
  void recordCalibration(const CalibrationEstimate& c);
  CalibrationEstimate calibration() {
    std::lock_guard<std::mutex> lk(mu_);
    return calibration_;
  }
  // The IMU's in-situ noise densities the prediction uses (imu_noise_estimator.hpp).
  void recordImuNoise(const ImuNoiseDensity& n);
  // The filter stopped for good (reported as ERROR from now on).
  void recordStop(const std::string& why);
  // A frame's correction reached the outputs `seconds` after its image was
  // taken (ROS clock now minus the frame stamp: front end, transport and
  // back end together). Kept over the whole run.
  void recordLatency(double seconds) { latency_.add(seconds); }

  // --- diagnostics timer ---
  // Rates and per-frame means over the period since the previous call;
  // `frames_dropped` is the mailbox's count (newer frame arrived first),
  // `input_resubscriptions` the input topics' (watched_subscriber.hpp).
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat, std::uint64_t frames_dropped,
                std::uint64_t input_resubscriptions);

 private:
  static void addCalibration(diagnostic_updater::DiagnosticStatusWrapper& stat, const CalibrationEstimate& c);
  // Sums of the per-stage figures since the last report.
  struct StageStats {
    int n = 0;
    IterationReport sum;
  };

  const bool use_imu_;
  hapi_nodelet_kit::LatencyHistogram latency_;  // its own lock
  std::mutex mu_;
  StageStats stages_;
  std::string last_filter_error_;
  std::string stopped_;  // why the filter stopped; empty while it runs
  std::string backend_name_ = "none (waiting for the first frame)";
  std::size_t backend_memory_ = 0;
  int n_landmarks_ = 0;
  CalibrationEstimate calibration_;
  ImuNoiseDensity imu_noise_;
  // Counter values and time of the previous report (for the rates);
  // diagnostics timer only.
  std::uint64_t prev_outputs_ = 0, prev_accepted_ = 0, prev_processed_ = 0, prev_rejected_ = 0, prev_dropped_ = 0,
                prev_scene_moving_ = 0, prev_vision_led_ = 0, prev_awaiting_imu_ = 0;
  ros::WallTime prev_time_;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
