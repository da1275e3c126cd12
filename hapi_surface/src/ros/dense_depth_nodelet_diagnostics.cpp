// DenseDepthDiagnostics (dense_depth_nodelet_diagnostics.hpp).
#include "dense_depth_nodelet_diagnostics.hpp"

#include <algorithm>

namespace hapi_surface {

void DenseDepthDiagnostics::dropped(const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++dropped_[reason];
}

void DenseDepthDiagnostics::rejected(const std::string& reason, const std::string& detail) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++rejected_[reason];
  ++win_rejected_;
  last_rejected_ = reason + ": " + detail;
}

void DenseDepthDiagnostics::published(double ms, double valid_fraction) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++published_;
  ++win_published_;
  win_ms_ += ms;
  win_max_ms_ = std::max(win_max_ms_, ms);
  win_valid_ += valid_fraction;
}

void DenseDepthDiagnostics::produce(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  using diagnostic_msgs::DiagnosticStatus;
  if (win_rejected_ > 0 && win_published_ == 0)
    stat.summary(DiagnosticStatus::ERROR, "every keyframe rejected: " + last_rejected_);
  else if (win_rejected_ > 0)
    stat.summary(DiagnosticStatus::WARN, "some keyframes rejected: " + last_rejected_);
  else if (published_ == 0)
    stat.summary(DiagnosticStatus::WARN, "no depth published yet");
  else
    stat.summary(DiagnosticStatus::OK, "publishing depth");
  stat.add("pairs", pairs_);
  stat.add("keyframes", keyframes_);
  stat.add("published", published_);
  stat.add("dropped", hapi_frontend::counterTotal(dropped_));
  hapi_frontend::addCounters(stat, "dropped.", dropped_);
  stat.add("rejected", hapi_frontend::counterTotal(rejected_));
  hapi_frontend::addCounters(stat, "rejected.", rejected_);
  const double n = static_cast<double>(std::max<std::uint64_t>(1, win_published_));
  stat.add("match_ms_mean", win_ms_ / n);
  stat.add("match_ms_max", win_max_ms_);
  stat.add("valid_fraction_mean", win_valid_ / n);
  win_published_ = win_rejected_ = 0;
  win_ms_ = win_max_ms_ = win_valid_ = 0;
}

}  // namespace hapi_surface
