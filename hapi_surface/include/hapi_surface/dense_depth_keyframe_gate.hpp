// Which stereo frames become depth keyframes: the first, then the first at
// least 1/rate after the last one taken; a stamp that jumps back (bag loop,
// simulator restart) starts afresh. ROS-free.
#pragma once

#include <cstdint>

namespace hapi_surface {

class DenseDepthKeyframeGate {
 public:
  explicit DenseDepthKeyframeGate(double rate_hz) : period_ns_(static_cast<std::int64_t>(1e9 / rate_hz)) {}
  bool take(std::int64_t stamp_ns) {
    if (has_last_ && stamp_ns >= last_ns_ && stamp_ns - last_ns_ < period_ns_) return false;
    has_last_ = true;
    last_ns_ = stamp_ns;
    return true;
  }

 private:
  std::int64_t period_ns_;
  std::int64_t last_ns_ = 0;
  bool has_last_ = false;
};

}  // namespace hapi_surface
