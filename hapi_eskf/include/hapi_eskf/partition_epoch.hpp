// The epoch rule of the exact partitioned update (docs/DESIGN.md
// "Partitioned update"), one copy for its CPU and CUDA variants.
//
// Observed landmarks that are not active yet join the active part (exact, no
// flush). When they are the majority of the observed ones (the view jumped),
// joining is no cheaper than the dense update (their basis rows would make
// the next flush cost as much), so the backend flushes, updates the stored C
// densely and starts a new epoch in which the observed landmarks are active
// (joined while Psi = 0: cheap).
#pragma once

#include "hapi_eskf/covariance_backend.hpp"

#include <vector>

namespace hapi_eskf {
namespace partition {

struct EpochStep {
  // true: flush, dense update, start an epoch, then join `join`;
  // false: join `join`, then the partitioned update.
  bool new_epoch = false;
  std::vector<int> join;  // slots: every observed one (new epoch) or the passive ones
};

// `active_pos[slot]` < 0: the landmark in `slot` is passive.
inline EpochStep planEpochStep(const std::vector<MeasurementBlock>& blocks, const std::vector<int>& active_pos) {
  EpochStep step;
  for (const MeasurementBlock& b : blocks)
    if (active_pos[b.slot] < 0) step.join.push_back(b.slot);
  step.new_epoch = 2 * step.join.size() > blocks.size();
  if (step.new_epoch) {
    step.join.clear();
    for (const MeasurementBlock& b : blocks) step.join.push_back(b.slot);
  }
  return step;
}

}  // namespace partition
}  // namespace hapi_eskf
