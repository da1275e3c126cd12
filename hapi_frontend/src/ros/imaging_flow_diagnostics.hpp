// Thread-safe counters of ImagingFlowNodelet, published as one
// diagnostic_updater task: frames, flows published by status, restarts by
// reason, bad images by reason, tracker time and inliers, the tracker's
// backend (CPU or CUDA, and why not CUDA where it was asked for).
#pragma once

#include "diagnostic_counters.hpp"
#include "hapi_frontend/image_flow_tracker.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace hapi_frontend {

class ImagingFlowDiagnostics {
 public:
  void frame() { bump(&frames_); }
  // A flow message left (any status), `ms` the tracker's time on the frame.
  void published(const ImageFlowResult& result, double ms);
  void badImage(const std::string& reason, const std::string& detail);
  void backend(const std::string& status) {
    std::lock_guard<std::mutex> lock(mutex_);
    backend_ = status;
  }

  void produce(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::uint64_t badImages(const std::string& reason) const;

 private:
  void bump(std::uint64_t* counter) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++*counter;
  }
  mutable std::mutex mutex_;
  std::uint64_t frames_ = 0, flows_ = 0, flows_ok_ = 0, too_few_ = 0;
  ReasonCounters restarts_, bad_;
  std::string last_bad_;
  std::string backend_;
  // Window since the last produce().
  ros::WallTime window_start_ = ros::WallTime::now();
  std::uint64_t win_frames_ = 0, win_ok_ = 0, win_bad_ = 0, win_inliers_ = 0, win_consistent_ = 0;
  double win_ms_ = 0, win_max_ms_ = 0;
};

}  // namespace hapi_frontend
