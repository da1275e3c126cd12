// The map record and the bookkeeping policy (landmark_book.hpp).
#include "hapi_eskf/backend/landmark_book.hpp"

#include "hapi_eskf/backend/removal_plan.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hapi_eskf {

void LandmarkBook::clear() {
  ids_.clear();
  positions_.clear();
  first_estimates_.clear();
  colours_.clear();
  times_observed_.clear();
  last_seen_.clear();
}

std::vector<int> LandmarkBook::byResponse(const StereoFrame& frame) {
  std::vector<int> order(frame.measurements.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return frame.measurements[a].response > frame.measurements[b].response;
  });
  return order;
}

std::vector<int> LandmarkBook::chooseUpdates(const Association& assoc, const std::vector<int>& by_response,
                                             const PoolSettings& settings) {
  std::vector<int> used;
  for (int i : by_response)
    if (assoc.slot[i] >= 0 && static_cast<int>(used.size()) < settings.max_update_landmarks) used.push_back(i);
  return used;
}

std::vector<int> LandmarkBook::chooseAdditions(const Association& assoc, const std::vector<int>& by_response,
                                               const PoolSettings& settings) const {
  const int max_add =
      size() == 0 && settings.bootstrap_landmarks > 0 ? settings.bootstrap_landmarks : settings.max_new_landmarks;
  std::vector<int> add;
  for (int i : by_response)
    if (assoc.may_add[i] && static_cast<int>(add.size()) < max_add) add.push_back(i);
  return add;
}

std::vector<int> LandmarkBook::chooseRemovals(int n_additions, const std::vector<char>& protected_slot,
                                              const PoolSettings& settings) const {
  const int K = size();
  const int free_slots = settings.max_landmarks - K;
  if (n_additions <= free_slots) return {};
  const int target = std::min<int>(
      n_additions, static_cast<int>(std::ceil(settings.full_pool_add_fraction * settings.max_new_landmarks - 1e-9)));
  int n_evict = std::max(0, target - free_slots);
  std::vector<int> evictable;
  for (int k = 0; k < K; ++k)
    if (!protected_slot[k]) evictable.push_back(k);
  n_evict = std::min<int>(n_evict, static_cast<int>(evictable.size()));
  if (n_evict <= 0) return {};
  const int keep = settings.full_pool_keep_observations;
  const auto kept = [&](int k) { return keep > 0 && times_observed_[k] >= keep; };
  std::partial_sort(evictable.begin(), evictable.begin() + n_evict, evictable.end(), [&](int a, int b) {
    if (kept(a) != kept(b)) return kept(b);
    if (last_seen_[a] != last_seen_[b]) return last_seen_[a] < last_seen_[b];
    if (times_observed_[a] != times_observed_[b]) return times_observed_[a] < times_observed_[b];
    return ids_[a] < ids_[b];
  });
  std::vector<int> evict(evictable.begin(), evictable.begin() + n_evict);
  std::sort(evict.begin(), evict.end());
  return evict;
}

int LandmarkBook::additionsThatFit(int n_additions, const PoolSettings& settings) const {
  return std::min(n_additions, settings.max_landmarks - size());
}

void LandmarkBook::observe(int slot, double stamp, const std::array<uint8_t, 3>& rgb) {
  ++times_observed_[slot];
  last_seen_[slot] = stamp;
  colours_[slot] = rgb;
}

void LandmarkBook::correct(const Eigen::VectorXd& dx, int pose_dim) {
  for (int k = 0; k < size(); ++k) positions_[k] += dx.segment<3>(landmarkRow(k, pose_dim));
}

void LandmarkBook::remove(const std::vector<int>& slots) {
  const int K = size();
  const std::vector<SlotMove> moves = tailFillMoves(K, slots);
  const int K_new = K - static_cast<int>(slots.size());
  applyRemoval(moves, K_new, &ids_);
  applyRemoval(moves, K_new, &positions_);
  applyRemoval(moves, K_new, &first_estimates_);
  applyRemoval(moves, K_new, &colours_);
  applyRemoval(moves, K_new, &times_observed_);
  applyRemoval(moves, K_new, &last_seen_);
}

uint64_t LandmarkBook::add(const Vec3& position, const std::array<uint8_t, 3>& rgb, double stamp) {
  return add(position, rgb, stamp, position);
}

uint64_t LandmarkBook::add(const Vec3& position, const std::array<uint8_t, 3>& rgb, double stamp,
                           const Vec3& first_estimate) {
  ids_.push_back(next_id_++);
  positions_.push_back(position);
  first_estimates_.push_back(first_estimate);
  colours_.push_back(rgb);
  times_observed_.push_back(1);
  last_seen_.push_back(stamp);
  return ids_.back();
}

uint64_t LandmarkBook::addPrior(const Vec3& position, int times_observed, double stamp) {
  const uint64_t id = add(position, {{128, 128, 128}}, stamp);
  times_observed_.back() = times_observed;
  return id;
}

std::vector<LandmarkInfo> LandmarkBook::info(const std::vector<Mat3>& cov) const {
  std::vector<LandmarkInfo> out(ids_.size());
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    out[k].id = ids_[k];
    out[k].position = positions_[k];
    out[k].covariance = k < cov.size() ? cov[k] : Mat3::Zero();
    out[k].rgb = colours_[k];
    out[k].times_observed = times_observed_[k];
    out[k].last_seen = last_seen_[k];
  }
  return out;
}

}  // namespace hapi_eskf
