// Whether the filter's pose at a stamp is settled enough to fuse a keyframe
// taken then (docs/SURFACE.md "Settle rule"): the filter has given
// poses for at least settle_time, and its pose uncertainty (odometry) at
// the stamp is within settle_position_std / settle_rotation_std.
#pragma once

#include "hapi_surface/surface_settings.hpp"

#include <deque>
#include <optional>

namespace hapi_surface {

// The filter's pose uncertainty at one stamp: standard deviations of the
// position (sqrt of the position covariance's trace, m) and of the rotation
// (same, rad).
struct PoseUncertainty {
  double stamp = 0;
  double position_std = 0;
  double rotation_std = 0;
};

class SettleGate {
 public:
  explicit SettleGate(const SurfaceSettings& s) : settings_(s) {}

  // The filter gave a pose at `stamp` (a depth frame's TF): the tracking
  // time counts from the first one, or from the first uncertainty.
  void notePose(double stamp);
  // An uncertainty (odometry), stamps increasing; older than kHistory
  // before the newest are forgotten.
  void addUncertainty(const PoseUncertainty& u);

  // The rule. Without any uncertainty received (a back end that publishes
  // no odometry) only the tracking time counts; once some arrived, the
  // newest one at or before `stamp` must pass (none: not settled).
  bool settled(double stamp) const;

  // Length of the uncertainty history kept, s (a depth keyframe reaches
  // the surface well within it: it waits only for its TF).
  static constexpr double kHistory = 10.0;

 private:
  SurfaceSettings settings_;
  std::optional<double> start_;
  std::deque<PoseUncertainty> history_;
};

}  // namespace hapi_surface
