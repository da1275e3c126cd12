// Counters of hapi_surface/SurfaceNodelet and its /diagnostics status.
// Atomics: counted from any callback thread without a lock.
#pragma once

#include "hapi_surface/surface_status.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace hapi_surface {
namespace ros_glue {

struct SurfaceStatistics {
  using Counter = std::atomic<std::uint64_t>;
  Counter depth_received{0}, depth_rejected{0}, depth_no_tf{0}, keyframes{0}, depth_skipped{0};
  Counter keyframes_unsettled{0}, odom_rejected{0};
  Counter depth_out_of_order{0}, time_jumps{0};
  Counter confidence_missing{0}, camera_info_rejected{0};
  Counter imaging_received{0}, imaging_projected{0}, imaging_rejected{0}, imaging_no_tf{0}, imaging_throttled{0};
  Counter rebuilds{0}, meshes_published{0}, saves{0}, saves_failed{0};
  std::atomic<std::uint64_t> vertices{0}, faces{0}, keyframes_stored{0};
  std::atomic<std::uint64_t> keyframes_waiting{0}, early_keyframes_fused{0}, early_keyframes_discarded{0};
  std::atomic<std::uint64_t> keyframes_registered{0}, keyframes_unregistered{0};
  std::atomic<bool> on_gpu{false};

  // A rejected input, counted under its reason too.
  void reject(Counter* counter, SurfaceStatus why);

  // WARN when depth comes but none becomes a keyframe or all is rejected,
  // or imaging frames come but none is projected; else OK.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  std::mutex mu_;
  std::map<std::string, std::uint64_t> reasons_;
  std::uint64_t last_depth_ = 0, last_used_ = 0, last_imaging_ = 0, last_projected_ = 0;
};

}  // namespace ros_glue
}  // namespace hapi_surface
