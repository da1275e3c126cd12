// FrontendDiagnostics (frontend_diagnostics.hpp): counters and the status task.
#include "frontend_diagnostics.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <algorithm>

namespace hapi_frontend {

void FrontendDiagnostics::frameProcessed(const StereoFrameResult& r) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++processed_;
  ++win_frames_;
  win_landmarks_ += r.landmarks.size();
  win_times_.convert += r.times.convert;
  win_times_.detect_left += r.times.detect_left;
  win_times_.detect_right += r.times.detect_right;
  win_times_.undistort += r.times.undistort;
  win_times_.match += r.times.match;
  win_times_.triangulate += r.times.triangulate;
  win_times_.total += r.times.total;
  win_max_total_ms_ = std::max(win_max_total_ms_, r.times.total);
  last_landmarks_ = static_cast<int>(r.landmarks.size());
  last_matches_ = r.n_matches;
  last_left_ = r.n_left;
  last_right_ = r.n_right;
  last_used_gpu_ = r.used_gpu;
}

void FrontendDiagnostics::rejected(const std::string& reason, const std::string& detail) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++rejected_[reason];
  ++win_rejects_;
  last_reject_ = reason + ": " + detail;
}

void FrontendDiagnostics::dropped(const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++dropped_[reason];
}

void FrontendDiagnostics::timeReset() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++time_resets_;
}

uint64_t FrontendDiagnostics::rejectedCount(const std::string& reason) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = rejected_.find(reason);
  return it == rejected_.end() ? 0 : it->second;
}

void FrontendDiagnostics::produce(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-6, (now - window_start_).toSec());
  const double n = static_cast<double>(std::max<uint64_t>(1, win_frames_));

  using diagnostic_msgs::DiagnosticStatus;
  if (win_rejects_ > 0) stat.summaryf(DiagnosticStatus::WARN, "%lu input frames rejected in the last %.1f s (%s)",
                                      static_cast<unsigned long>(win_rejects_), dt, last_reject_.c_str());
  else if (win_frames_ == 0) stat.summary(DiagnosticStatus::WARN, "no stereo frames processed (waiting for images)");
  else stat.summary(DiagnosticStatus::OK, "processing");

  stat.add("processing rate [Hz]", win_frames_ / dt);
  stat.add("frames processed", processed_);
  stat.add("landmarks per frame (mean)", win_frames_ ? win_landmarks_ / n : 0.0);
  stat.add("landmarks last frame", last_landmarks_);
  stat.add("matches last frame", last_matches_);
  stat.add("keypoints left/right last frame", std::to_string(last_left_) + "/" + std::to_string(last_right_));
  stat.add("gpu used", last_used_gpu_);
  stat.add("time convert [ms]", win_times_.convert / n);
  stat.add("time detect_left [ms]", win_times_.detect_left / n);
  stat.add("time detect_right [ms]", win_times_.detect_right / n);
  stat.add("time undistort [ms]", win_times_.undistort / n);
  stat.add("time match [ms]", win_times_.match / n);
  stat.add("time triangulate [ms]", win_times_.triangulate / n);
  stat.add("time total [ms]", win_times_.total / n);
  stat.add("time total max [ms]", win_max_total_ms_);
  stat.add("time resets", time_resets_);
  // Image stamp to the published landmarks, over the run.
  const hapi_nodelet_kit::LatencyHistogram::Summary lat = latency_.summary();
  stat.add("latency stamp to landmarks p50 [ms]", lat.p50 * 1e3);
  stat.add("latency stamp to landmarks p99 [ms]", lat.p99 * 1e3);
  stat.add("latency stamp to landmarks max [ms]", lat.max * 1e3);
  stat.add("rejected total", counterTotal(rejected_));
  stat.add("dropped total", counterTotal(dropped_));
  addCounters(stat, "rejected.", rejected_);
  addCounters(stat, "dropped.", dropped_);
  if (!last_reject_.empty()) stat.add("last rejection", last_reject_);

  window_start_ = now;
  win_frames_ = win_rejects_ = win_landmarks_ = 0;
  win_times_ = StageTimesMs{};
  win_max_total_ms_ = 0;
}

}  // namespace hapi_frontend
