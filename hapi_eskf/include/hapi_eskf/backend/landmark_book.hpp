// The host record of the landmark map and the bookkeeping policy every back
// end follows (docs/DESIGN.md "Back ends", "One iteration"): per slot the id,
// world position (the mean), its first estimate (docs/DESIGN.md
// "First-estimate Jacobians"), colour, times observed and last seen, in the
// slot order of the back end's own storage; and the choices of one frame:
//  * measurements used in the update: the associated ones with the strongest
//    detector response, at most max_update_landmarks (response is
//    independent of the measurement noise, so this does not bias the update
//    the way "smallest innovation first" would);
//  * measurements added: the strongest of those that may start a landmark
//    (Association::may_add), at most max_new_landmarks, or
//    bootstrap_landmarks when the pool is empty;
//  * pool full: the least recently seen landmarks (ties: fewest
//    observations, then oldest id) not used in this frame's update are
//    removed so that min(#candidates, ceil(full_pool_add_fraction *
//    max_new_landmarks)) new landmarks fit; with full_pool_keep_observations
//    > 0, landmarks observed that often go only after all the others.
// The book does not own covariances or descriptors (the back end's storage
// does); removals apply the pool's one slot plan (removal_plan.hpp) so both
// stay in the same order.
#pragma once

#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/pool_settings.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace hapi_eskf {

class LandmarkBook {
 public:
  // Forgets every landmark; ids keep counting (unique for the book's lifetime).
  void clear();
  int size() const { return static_cast<int>(ids_.size()); }
  const std::vector<Vec3>& positions() const { return positions_; }
  // Where each landmark was first estimated (never corrected).
  const std::vector<Vec3>& firstEstimates() const { return first_estimates_; }
  const std::vector<uint64_t>& ids() const { return ids_; }
  const std::vector<double>& lastSeen() const { return last_seen_; }
  const std::vector<int>& timesObserved() const { return times_observed_; }
  Vec3& position(int slot) { return positions_[slot]; }

  // Measurement indices of the frame, strongest response first (stable:
  // ties keep frame order).
  static std::vector<int> byResponse(const StereoFrame& frame);
  // The associated measurements used in the update (policy above).
  static std::vector<int> chooseUpdates(const Association& assoc, const std::vector<int>& by_response,
                                        const PoolSettings& settings);
  // The measurements that would start landmarks (policy above), before the
  // pool's room is considered.
  std::vector<int> chooseAdditions(const Association& assoc, const std::vector<int>& by_response,
                                   const PoolSettings& settings) const;
  // Slots to remove (ascending) so that additions fit (policy above);
  // `protected_slot[k]` != 0 marks the landmarks of this frame's update.
  std::vector<int> chooseRemovals(int n_additions, const std::vector<char>& protected_slot,
                                  const PoolSettings& settings) const;
  // How many of n_additions fit now.
  int additionsThatFit(int n_additions, const PoolSettings& settings) const;

  // A landmark was used in an update at `stamp` (its colour follows the latest view).
  void observe(int slot, double stamp, const std::array<uint8_t, 3>& rgb);
  // Error-state correction of every landmark: position_k += dx[pose_dim + 3k .. +2].
  void correct(const Eigen::VectorXd& dx, int pose_dim);
  // Removes the slots (the back end's storage applies the same plan).
  void remove(const std::vector<int>& slots);
  // A new landmark at the next slot, observed once at `stamp`; returns its
  // id. Its first estimate is `position` unless given.
  uint64_t add(const Vec3& position, const std::array<uint8_t, 3>& rgb, double stamp);
  uint64_t add(const Vec3& position, const std::array<uint8_t, 3>& rgb, double stamp, const Vec3& first_estimate);
  // A landmark of a loaded map: seen `times_observed` times, last at `stamp`
  // (the load), so the pool's eviction policy treats it as any other.
  uint64_t addPrior(const Vec3& position, int times_observed, double stamp);

  // The map as LandmarkInfo, with the back end's marginal covariances (slot
  // order; missing entries are zero).
  std::vector<LandmarkInfo> info(const std::vector<Mat3>& covariances) const;

 private:
  uint64_t next_id_ = 1;
  std::vector<uint64_t> ids_;
  std::vector<Vec3> positions_;
  std::vector<Vec3> first_estimates_;
  std::vector<std::array<uint8_t, 3>> colours_;
  std::vector<int> times_observed_;
  std::vector<double> last_seen_;
};

}  // namespace hapi_eskf
