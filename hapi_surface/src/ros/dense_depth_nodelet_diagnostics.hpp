// Thread-safe counters of DenseDepthNodelet, published as one
// diagnostic_updater task: pairs received, keyframes taken and published,
// pairs dropped (busy worker, unpaired stamps), bad input by reason, the
// matcher's time and the valid fraction of the last window.
#pragma once

#include "diagnostic_counters.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include <cstdint>
#include <mutex>
#include <string>

namespace hapi_surface {

class DenseDepthDiagnostics {
 public:
  void pair() { bump(&pairs_); }
  void keyframe() { bump(&keyframes_); }
  void dropped(const std::string& reason);
  void rejected(const std::string& reason, const std::string& detail);
  void published(double ms, double valid_fraction);

  void produce(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  void bump(std::uint64_t* counter) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++*counter;
  }
  std::mutex mutex_;
  std::uint64_t pairs_ = 0, keyframes_ = 0, published_ = 0;
  hapi_frontend::ReasonCounters dropped_, rejected_;
  std::string last_rejected_;
  // Since the last produce().
  std::uint64_t win_published_ = 0, win_rejected_ = 0;
  double win_ms_ = 0, win_max_ms_ = 0, win_valid_ = 0;
};

}  // namespace hapi_surface
