// The epoch rule of the exact partitioned update (docs/DESIGN.md
// "Partitioned update"), one copy for its CPU and CUDA variants.
//
// Observed landmarks that are not active yet join the active part (exact, no
// flush). When they are the majority of the observed ones (the view jumped),
// joining is no cheaper than the dense update (their basis rows would make
// the next flush cost as much), so the backend flushes, updates the stored C
// densely and starts a new epoch in which the observed landmarks are active
// (joined while Psi = 0: cheap). Not so in the first update of an epoch that a
// staged flush began (staged_flush.hpp): its whole view is passive, but the
// dense update would first have to finish the pending correction, so the view
// joins (Psi = 0: cheap) and its rank update goes to the next flush, whose
// shares are spread over later updates.
#pragma once

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"

#include <algorithm>
#include <vector>

namespace hapi_eskf {
namespace partition {

struct EpochStep {
  // true: flush, dense update, start an epoch, then join `join`;
  // false: join `join`, then the partitioned update.
  bool new_epoch = false;
  std::vector<int> join;  // slots: every observed one (new epoch) or the passive ones
};

// `active_pos[slot]` < 0: the landmark in `slot` is passive. `after_staged_flush`:
// the epoch began at a staged flush and has had no update yet.
inline EpochStep planEpochStep(const std::vector<MeasurementBlock>& blocks, const std::vector<int>& active_pos,
                               bool after_staged_flush) {
  EpochStep step;
  for (const MeasurementBlock& b : blocks)
    if (active_pos[b.slot] < 0) step.join.push_back(b.slot);
  step.new_epoch = !after_staged_flush && 2 * step.join.size() > blocks.size();
  if (step.new_epoch) {
    step.join.clear();
    for (const MeasurementBlock& b : blocks) step.join.push_back(b.slot);
  }
  return step;
}

// Before a removal of `slots` (of `num_landmarks`): which slots go, the
// active landmarks that stay (old slots, in active order) and the rows of the
// active block that stay (the pose_dim pose rows, then 3 per kept active
// landmark).
struct KeptActive {
  std::vector<char> removed;  // per old slot
  std::vector<int> landmarks;
  std::vector<int> rows;
};
inline KeptActive keptAfterRemoval(const std::vector<int>& slots, int num_landmarks, int pose_dim,
                                   const std::vector<int>& active, const std::vector<int>& active_pos) {
  KeptActive kept;
  kept.removed.assign(num_landmarks, 0);
  for (int s : slots) kept.removed[s] = 1;
  for (int i = 0; i < pose_dim; ++i) kept.rows.push_back(i);
  for (int s : active)
    if (!kept.removed[s]) {
      kept.landmarks.push_back(s);
      for (int r = 0; r < 3; ++r) kept.rows.push_back(active_pos[s] + r);
    }
  return kept;
}

// After a removal of `kept.removed` whose kept landmarks moved between slots
// as `moves` say: the per-slot basis flags, the active list and positions
// (the kept active landmarks, in active order, after the pose_dim pose rows)
// and the basis list, renumbered to the new slots.
inline void renumberAfterRemoval(const KeptActive& kept, const std::vector<SlotMove>& moves, int pose_dim,
                                 std::vector<char>* in_basis, std::vector<int>* active,
                                 std::vector<int>* active_pos, std::vector<int>* basis) {
  std::vector<int> new_of_old(kept.removed.size());  // new slot of old slot k, -1 when removed
  for (std::size_t k = 0; k < new_of_old.size(); ++k) new_of_old[k] = kept.removed[k] ? -1 : static_cast<int>(k);
  for (const SlotMove& mv : moves) new_of_old[mv.from] = mv.to;
  std::vector<char> basis_new(in_basis->size(), 0);
  for (std::size_t k = 0; k < new_of_old.size(); ++k)
    if (new_of_old[k] >= 0) basis_new[new_of_old[k]] = (*in_basis)[k];
  in_basis->swap(basis_new);
  active->clear();
  std::fill(active_pos->begin(), active_pos->end(), -1);
  for (std::size_t i = 0; i < kept.landmarks.size(); ++i) {
    const int s = new_of_old[kept.landmarks[i]];
    active->push_back(s);
    (*active_pos)[s] = pose_dim + 3 * static_cast<int>(i);
  }
  for (int& s : *basis) s = new_of_old[s];
}

}  // namespace partition
}  // namespace hapi_eskf
