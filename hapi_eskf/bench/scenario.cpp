#include "scenario.hpp"
#include "hapi_eskf/random_draw.hpp"

#include "hapi_eskf/backend/removal_plan.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

namespace hapi_eskf {
namespace bench {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Records the first failing call; the iteration stops there (its state is
// then unusable for timing, and the benchmark reports the failure).
bool check(Status s, const char* stage, StageTimes* st) {
  if (s == Status::kOk) return true;
  st->ok = false;
  st->failure = std::string(stage) + ": " + toString(s);
  return false;
}

}  // namespace

Scenario::Scenario(std::unique_ptr<CovarianceBackend> backend, int K, int visible, int fresh, unsigned seed,
                   Visibility visibility, int sweep_step)
    : b_(std::move(backend)),
      K_(K),
      visible_(visible),
      fresh_(fresh),
      rng_(seed),
      visibility_(visibility),
      sweep_step_(sweep_step) {
  s_.max_landmarks = K;
  s_.max_new_landmarks = fresh;
  s_.max_update_landmarks = visible;
  pose_.v = Vec3(0.0, 0.0, 0.5);
  pose_.w = Vec3(0.0, 0.05, 0.0);
}

std::vector<uint8_t> Scenario::randomDescriptor() {
  std::vector<uint8_t> d(kDescLen);
  std::uniform_int_distribution<int> u(0, 255);
  for (auto& x : d) x = static_cast<uint8_t>(u(rng_));
  return d;
}

NewLandmarkBlock Scenario::newBlock(const Vec3& z, const std::vector<uint8_t>& d, Vec3* position) const {
  NewLandmarkBlock nb;
  newLandmarkJacobian(pose_, z, &nb.G_pose, &nb.G_z);
  // Stereo-like noise: depth worse than the lateral coordinates.
  nb.Cz = Vec3(1e-4, 1e-4, 4e-4 * z.z() * z.z()).asDiagonal();
  nb.descriptor = d.data();
  *position = initLandmark(pose_, z);
  return nb;
}

bool Scenario::fill() {
  Mat12 C0 = Mat12::Zero();
  C0.diagonal() << 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 0.04, 0.04, 0.04, 0.25, 0.25, 0.25;
  if (b_->reset(C0) != Status::kOk) return false;
  std::normal_distribution<double> lat(0.0, 2.0);
  std::uniform_real_distribution<double> depth(2.0, 10.0);
  while (static_cast<int>(positions_.size()) < K_) {
    // Batches of at most 200 (a frame's worth): a partitioned backend's
    // active blocks stay sized for frames (the landmarks drawn do not depend
    // on the batch size).
    const int m = std::min(200, K_ - static_cast<int>(positions_.size()));
    std::vector<std::vector<uint8_t>> d(m);
    std::vector<NewLandmarkBlock> blocks(m);
    for (int i = 0; i < m; ++i) {
      d[i] = randomDescriptor();
      Vec3 pos;
      blocks[i] = newBlock(Vec3(lat(rng_), lat(rng_), depth(rng_)), d[i], &pos);
      positions_.push_back(pos);
      desc_.push_back(d[i]);
      last_seen_.push_back(0.0);
      u_.push_back(std::uniform_real_distribution<double>(0.0, 1.0)(rng_));
    }
    if (b_->addLandmarks(blocks) != Status::kOk) return false;
  }
  return true;
}

std::vector<int> Scenario::visibleSlots(int K) {
  std::vector<int> seen(K);
  std::iota(seen.begin(), seen.end(), 0);
  const int n = std::min(visible_, K);
  if (visibility_ == Visibility::kRandom) {
    std::shuffle(seen.begin(), seen.end(), rng_);
  } else {
    cursor_ = std::fmod(cursor_ + static_cast<double>(sweep_step_) / K_, 1.0);
    auto ahead = [&](int k) { return std::fmod(u_[k] - cursor_ + 1.0, 1.0); };
    std::nth_element(seen.begin(), seen.begin() + n, seen.end(), [&](int a, int b) { return ahead(a) < ahead(b); });
  }
  seen.resize(n);
  return seen;
}

StageTimes Scenario::iterate() {
  StageTimes st;
  int flushes0 = 0;
  double flush_s0 = 0;
  const bool partitioned = partitionedFlushStats(*b_, &flushes0, &flush_s0);
  const auto t_start = Clock::now();
  const double dt = 1.0 / 30.0;

  // --- predict ---
  auto t0 = Clock::now();
  const Mat12 F = predictJacobian(pose_, dt, s_), Q = processNoise(dt, s_);
  if (!check(b_->predict(F, Q), "predict", &st)) return st;
  pose_ = predictPose(pose_, dt, s_);
  t_ += dt;
  st.predict = msSince(t0);

  // The frame (not timed: the front end's job): `visible_` pool landmarks
  // re-observed (1 cm noise, 2 flipped descriptor bits) and `fresh_` new points.
  const int K = b_->numLandmarks();
  const std::vector<int> seen = visibleSlots(K);
  StereoFrame frame;
  frame.stamp = t_;
  frame.descriptor_length = kDescLen;
  std::normal_distribution<double> noise(0.0, 0.01), lat(0.0, 2.0);
  std::uniform_real_distribution<double> depth(2.0, 10.0);
  std::uniform_int_distribution<int> bit(0, 8 * kDescLen - 1);
  std::vector<std::vector<uint8_t>> fresh_desc;
  for (std::size_t j = 0; j < seen.size() + fresh_; ++j) {
    StereoMeasurement m;
    m.frontend_id = static_cast<uint32_t>(j);
    m.Cz = 1e-4 * Mat3::Identity();
    m.response = static_cast<float>(j % 97);
    std::vector<uint8_t> d;
    if (j < seen.size()) {
      m.z = measure(pose_, positions_[seen[j]]) + drawVec3(noise, rng_);
      d = desc_[seen[j]];
      for (int f = 0; f < 2; ++f) {
        const int b = bit(rng_);
        d[b / 8] ^= static_cast<uint8_t>(1u << (b % 8));
      }
    } else {
      m.z = Vec3(lat(rng_), lat(rng_), depth(rng_));
      d = randomDescriptor();
    }
    frame.measurements.push_back(m);
    frame.descriptors.insert(frame.descriptors.end(), d.begin(), d.end());
  }

  // --- association (descriptor matching over the pool + Mahalanobis gate) ---
  t0 = Clock::now();
  Association assoc;
  if (!check(associate(frame, pose_, Mat6::Identity(), positions_, *b_, s_, &assoc), "association", &st)) return st;
  st.association = msSince(t0);

  // --- update ---
  t0 = Clock::now();
  std::vector<MeasurementBlock> blocks;
  std::vector<char> used(K, 0);
  for (std::size_t i = 0; i < frame.measurements.size() && static_cast<int>(blocks.size()) < visible_; ++i) {
    const int k = assoc.slot[i];
    if (k < 0) continue;
    MeasurementBlock b;
    b.slot = k;
    measurementJacobian(pose_, positions_[k], &b.H_pose, &b.H_landmark);
    b.R = frame.measurements[i].Cz;
    b.innovation = frame.measurements[i].z - measure(pose_, positions_[k]);
    blocks.push_back(b);
    used[k] = 1;
  }
  if (!blocks.empty()) {
    Eigen::VectorXd dx;
    if (!check(b_->update(blocks, &dx), "update", &st)) return st;
    {
      injectPose(&pose_, dx.head<kCameraMotionDim>());
      for (int k = 0; k < K; ++k) positions_[k] += dx.segment<3>(landmarkRow(k, kCameraMotionDim));
      for (int k = 0; k < K; ++k)
        if (used[k]) last_seen_[k] = t_;
    }
  }
  st.n_updated = static_cast<int>(blocks.size());
  st.update = msSince(t0);

  // --- removal: evict the least recently seen landmarks not used now ---
  t0 = Clock::now();
  std::vector<int> cand;
  for (int k = 0; k < K; ++k)
    if (!used[k]) cand.push_back(k);
  const int n_evict = std::min<int>(fresh_, static_cast<int>(cand.size()));
  std::partial_sort(cand.begin(), cand.begin() + n_evict, cand.end(),
                    [&](int a, int b) { return last_seen_[a] < last_seen_[b] || (last_seen_[a] == last_seen_[b] && a < b); });
  std::vector<int> evict(cand.begin(), cand.begin() + n_evict);
  std::sort(evict.begin(), evict.end());
  if (!check(b_->removeLandmarks(evict), "removal", &st)) return st;
  // The host mirror (positions, descriptors, ages) follows the same slot plan.
  {
    const std::vector<SlotMove> moves = tailFillMoves(K, evict);
    applyRemoval(moves, K - n_evict, &positions_);
    applyRemoval(moves, K - n_evict, &desc_);
    applyRemoval(moves, K - n_evict, &last_seen_);
    applyRemoval(moves, K - n_evict, &u_);
    st.removal_moved_landmarks = static_cast<int>(moves.size());
  }
  st.n_removed = n_evict;
  st.removal = msSince(t0);

  // --- addition: the fresh measurements ---
  t0 = Clock::now();
  std::vector<NewLandmarkBlock> nb;
  std::vector<std::vector<uint8_t>> nd;
  nd.reserve(fresh_);
  for (std::size_t i = seen.size(); i < frame.measurements.size(); ++i) {
    if (assoc.slot[i] >= 0 || static_cast<int>(positions_.size() + nb.size()) >= K_) continue;
    nd.emplace_back(frame.descriptors.begin() + i * kDescLen, frame.descriptors.begin() + (i + 1) * kDescLen);
    Vec3 pos;
    nb.push_back(newBlock(frame.measurements[i].z, nd.back(), &pos));
    positions_.push_back(pos);
    desc_.push_back(nd.back());
    last_seen_.push_back(t_);
    // Inside the current view (kSweep); unused by kRandom.
    u_.push_back(std::fmod(cursor_ + std::uniform_real_distribution<double>(0.0, 1.0)(rng_) * visible_ / K_, 1.0));
  }
  if (!check(b_->addLandmarks(nb), "addition", &st)) return st;
  st.n_added = static_cast<int>(nb.size());
  st.addition = msSince(t0);
  t0 = Clock::now();
  if (!check(b_->frameCompleted(), "frameCompleted", &st)) return st;
  st.deferred = msSince(t0);
  (void)t_start;
  if (partitioned) {
    int flushes1 = 0;
    double flush_s1 = 0;
    partitionedFlushStats(*b_, &flushes1, &flush_s1);
    st.flushes = flushes1 - flushes0;
    st.flush_ms = 1e3 * (flush_s1 - flush_s0);
  }
  // Full iteration = the six stages (frame synthesis above is the front end's work).
  st.total = st.predict + st.association + st.update + st.removal + st.addition + st.deferred;
  return st;
}

}  // namespace bench
}  // namespace hapi_eskf
