// ImagingFlowDiagnostics (imaging_flow_diagnostics.hpp).
#include "imaging_flow_diagnostics.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <algorithm>

namespace hapi_frontend {

void ImagingFlowDiagnostics::published(const ImageFlowResult& r, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++flows_;
  ++win_frames_;
  win_ms_ += ms;
  win_max_ms_ = std::max(win_max_ms_, ms);
  if (r.status == FlowStatus::kOk) {
    ++flows_ok_;
    ++win_ok_;
    win_inliers_ += r.inliers;
    win_consistent_ += r.consistent;
  } else if (r.status == FlowStatus::kTooFewFeatures) {
    ++too_few_;
  } else {
    ++restarts_[r.restart_reason];
  }
}

void ImagingFlowDiagnostics::badImage(const std::string& reason, const std::string& detail) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++bad_[reason];
  ++win_bad_;
  last_bad_ = reason + ": " + detail;
}

std::uint64_t ImagingFlowDiagnostics::badImages(const std::string& reason) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = bad_.find(reason);
  return it == bad_.end() ? 0 : it->second;
}

void ImagingFlowDiagnostics::produce(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double dt = std::max(1e-6, (now - window_start_).toSec());
  using diagnostic_msgs::DiagnosticStatus;
  if (win_bad_ > 0)
    stat.summaryf(DiagnosticStatus::WARN, "%lu bad images in the last %.1f s (%s)",
                  static_cast<unsigned long>(win_bad_), dt, last_bad_.c_str());
  else if (win_frames_ == 0) stat.summary(DiagnosticStatus::WARN, "no images (waiting for the imaging camera)");
  else if (win_ok_ == 0) stat.summary(DiagnosticStatus::WARN, "no valid flow (too few features?)");
  else stat.summary(DiagnosticStatus::OK, "measuring");
  const double n = static_cast<double>(std::max<std::uint64_t>(1, win_frames_));
  stat.add("flow rate [Hz]", win_frames_ / dt);
  stat.add("frames", frames_);
  stat.add("flows published", flows_);
  stat.add("flows ok", flows_ok_);
  stat.add("flows too few features", too_few_);
  stat.add("inliers per valid flow (mean)", win_ok_ ? static_cast<double>(win_inliers_) / win_ok_ : 0.0);
  stat.add("forward-backward consistent tracks per valid flow (mean)",
           win_ok_ ? static_cast<double>(win_consistent_) / win_ok_ : 0.0);
  stat.add("time tracker [ms]", win_ms_ / n);
  stat.add("time tracker max [ms]", win_max_ms_);
  stat.add("backend", backend_);
  stat.add("restarts", counterTotal(restarts_));
  stat.add("bad images", counterTotal(bad_));
  addCounters(stat, "restart.", restarts_);
  addCounters(stat, "rejected.", bad_);
  if (!last_bad_.empty()) stat.add("last bad image", last_bad_);
  window_start_ = now;
  win_frames_ = win_ok_ = win_bad_ = win_inliers_ = win_consistent_ = 0;
  win_ms_ = win_max_ms_ = 0;
}

}  // namespace hapi_frontend
