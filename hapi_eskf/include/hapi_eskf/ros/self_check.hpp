// The back end's self-checks, published as their own diagnostic_updater
// task ("self-check"), each judged over the period since the previous
// report and named with its number and likely cause (docs/CALIBRATION.md
// "Self-checks"):
//  check.clock           IMU stamps beyond ~imu_max_frame_offset of the image
//                        stamps, or the online time-offset estimate moved
//                        beyond ~check_max_time_offset_change from
//                        imu_time_offset: images and IMU not on one clock
//  check.imu             no IMU samples while landmarks arrive, or most of
//                        them dropped (the dominant reason named): IMU not fused
//  check.initialisation  not tracking after ~check_init_timeout, and why (no
//                        landmarks, the gravity alignment waiting for IMU)
//  check.landmarks       fewer than ~check_min_landmarks per frame reach the filter
// Threads: frameMeasured from the worker, produce from the diagnostics timer.
#pragma once

#include "hapi_eskf/ros/params.hpp"
#include "hapi_eskf/ros/statistics.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

class SelfCheck {
 public:
  SelfCheck(const NodeletParams& params, NodeletStatistics& stats);
  // A frame reached the filter with `n` landmarks.
  void frameMeasured(int n);
  void produce(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  struct Level {
    unsigned char level;
    std::string message;  // empty: passed
  };
  // The period's counter increments.
  struct Delta {
    std::uint64_t accepted = 0, received = 0, dropped = 0, far = 0;
  };
  Level clockCheck(const Delta& d) const;
  Level imuCheck(const Delta& d, double dt) const;
  Level initialisationCheck(ros::WallTime now) const;
  Level landmarksCheck(double median_landmarks) const;
  // The drop reason with the most samples since the start, with its cause.
  std::string dominantDropCause() const;

  const NodeletParams& params_;
  NodeletStatistics& stats_;
  std::mutex mu_;
  std::vector<double> landmarks_;  // per frame since the last report
  // Diagnostics timer only.
  const ros::WallTime start_ = ros::WallTime::now();
  ros::WallTime prev_time_ = start_, first_frame_time_;
  Delta prev_;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
