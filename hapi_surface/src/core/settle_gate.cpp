#include "hapi_surface/settle_gate.hpp"

#include <algorithm>

namespace hapi_surface {

void SettleGate::notePose(double stamp) {
  if (!start_ || stamp < *start_) start_ = stamp;
}

void SettleGate::addUncertainty(const PoseUncertainty& u) {
  if (!history_.empty() && u.stamp <= history_.back().stamp) return;
  notePose(u.stamp);
  history_.push_back(u);
  while (history_.front().stamp < u.stamp - kHistory) history_.pop_front();
}

bool SettleGate::settled(double stamp) const {
  if (!start_ || stamp - *start_ < settings_.settle_time) return false;
  if (history_.empty()) return true;
  // The newest uncertainty at or before the stamp.
  const auto after = std::upper_bound(history_.begin(), history_.end(), stamp,
                                      [](double t, const PoseUncertainty& u) { return t < u.stamp; });
  if (after == history_.begin()) return false;
  const PoseUncertainty& u = *std::prev(after);
  const bool position_ok = settings_.settle_position_std <= 0 || u.position_std <= settings_.settle_position_std;
  const bool rotation_ok = settings_.settle_rotation_std <= 0 || u.rotation_std <= settings_.settle_rotation_std;
  return position_ok && rotation_ok;
}

}  // namespace hapi_surface
