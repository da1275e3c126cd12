// Thread-safe counters and timing statistics of the front end, published as
// one diagnostic_updater task: processing rate, mean per-stage times
// (StageTimesMs), landmarks per frame, and cumulative per-reason rejection
// and drop counters ("rejected.<reason>", "dropped.<reason>"), which tests and
// operators read from /diagnostics.
#pragma once

#include "diagnostic_counters.hpp"
#include "hapi_frontend/stereo_pipeline.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <hapi_nodelet_kit/latency_histogram.hpp>
#include <ros/time.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace hapi_frontend {

class FrontendDiagnostics {
 public:
  void frameProcessed(const StereoFrameResult& result);
  // The frame's landmarks were published `seconds` after the image was
  // taken (ROS clock now minus the image stamp). Kept over the whole run.
  void landmarksPublished(double seconds) { latency_.add(seconds); }
  void rejected(const std::string& reason, const std::string& detail);
  void dropped(const std::string& reason);
  void timeReset();

  // diagnostic_updater task; rates are computed over the time since the
  // previous call.
  void produce(diagnostic_updater::DiagnosticStatusWrapper& stat);

  uint64_t rejectedCount(const std::string& reason) const;

 private:
  hapi_nodelet_kit::LatencyHistogram latency_;  // its own lock
  mutable std::mutex mutex_;
  uint64_t processed_ = 0, time_resets_ = 0;
  ReasonCounters rejected_, dropped_;
  std::string last_reject_;
  // Window since the last produce().
  ros::WallTime window_start_ = ros::WallTime::now();
  uint64_t win_frames_ = 0, win_rejects_ = 0, win_landmarks_ = 0;
  StageTimesMs win_times_;
  double win_max_total_ms_ = 0;
  int last_landmarks_ = 0, last_matches_ = 0, last_left_ = 0, last_right_ = 0;
  bool last_used_gpu_ = false;
};

}  // namespace hapi_frontend
