// A random backend sequence with spatial structure, driven into two backends
// with the same calls (docs/DESIGN.md "Partitioned update"): landmarks belong
// to areas, each frame observes its current area, the area switches,
// landmarks are added in the current area and removed anywhere (also active
// and basis ones). Shared by the CPU variant tests and the GPU partitioned
// tests, so both compare against the same sequences.
#pragma once

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "test_random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace testing_sequence {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;
using testing_random::Rng;
using testing_random::randomBlock;
using testing_random::randomNewBlock;

// max |a - b| / max |b| (1e-300 floor).
inline double relDiff(const MatX& a, const MatX& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return 1e300;
  if (a.size() == 0) return 0.0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

inline PoseMat randomF(Rng& r, int P) {
  PoseMat F = PoseMat::Identity(P, P);
  for (int i = 0; i < P; ++i)
    for (int j = 0; j < P; ++j) F(i, j) += r.n(0.05);
  return F;
}

struct Counts {
  int updates = 0, additions = 0, removals = 0, switches = 0, checkpoints = 0;
};

// Drives `test` and `ref` with the same calls; every update's dx and nis, and
// the marginals of the next frame's candidates, are compared at once (they
// need no flush); the whole C at every `dense_every`-th frame and at the end.
inline void runSequence(CovarianceBackend* test, CovarianceBackend* ref, unsigned seed, int frames, int dense_every,
                 int P, Counts* counts) {
  const double tol = 1e-9;
  Rng r(seed);
  const int dlen = 8, cap = test->capacity(), areas = 6;
  const PoseMat C0 = r.spd(P, 0.01);
  ASSERT_EQ(test->reset(C0), Status::kOk);
  ASSERT_EQ(ref->reset(C0), Status::kOk);
  std::vector<int> area_of;  // per slot, kept in the removal plan's slot order
  std::vector<std::vector<uint8_t>> store;
  auto add = [&](int m, int area) {
    std::vector<NewLandmarkBlock> blocks;
    for (int i = 0; i < m; ++i) {
      store.push_back(r.bytes(dlen));
      blocks.push_back(randomNewBlock(r, store.back()));
    }
    for (int i = 0; i < m; ++i) blocks[i].descriptor = store[store.size() - m + i].data();
    ASSERT_EQ(test->addLandmarks(blocks), Status::kOk);
    ASSERT_EQ(ref->addLandmarks(blocks), Status::kOk);
    for (int i = 0; i < m; ++i) area_of.push_back(area);
    counts->additions += m;
  };
  // A first map: 12 landmarks in every area.
  for (int a = 0; a < areas; ++a) add(12, a);
  int area = 0;
  for (int f = 0; f < frames; ++f) {
    const std::string where = "frame " + std::to_string(f);
    if (r.i(0, 9) == 0) {  // area switch (sometimes a jump across the map)
      area = r.i(0, areas - 1);
      ++counts->switches;
    }
    const PoseMat F = randomF(r, P);
    PoseMat Q = PoseMat::Zero(P, P);
    Q.diagonal().tail(P - 6).setConstant(1e-4);
    ASSERT_EQ(test->predict(F, Q), Status::kOk);
    ASSERT_EQ(ref->predict(F, Q), Status::kOk);
    ASSERT_LE(relDiff(test->poseCovariance(), ref->poseCovariance()), tol) << where;
    // Candidates: most of the current area plus a few from anywhere.
    const int K = test->numLandmarks();
    std::vector<int> seen;
    for (int k = 0; k < K; ++k)
      if ((area_of[k] == area && r.i(0, 3) != 0) || r.i(0, 60) == 0) seen.push_back(k);
    if (seen.size() > 40) seen.resize(40);
    if (!seen.empty()) {
      std::vector<Mat9> mt(seen.size()), mr(seen.size());
      ASSERT_EQ(test->marginals(seen, &mt), Status::kOk);
      ASSERT_EQ(ref->marginals(seen, &mr), Status::kOk);
      for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_LE(relDiff(mt[i], mr[i]), tol) << where << " slot " << seen[i];
      std::vector<MeasurementBlock> blocks;
      for (int s : seen) blocks.push_back(randomBlock(r, s, 0.01));
      VecX dxt, dxr;
      double nist = 0, nisr = 0;
      ASSERT_EQ(test->update(blocks, &dxt, &nist), Status::kOk) << where;
      ASSERT_EQ(ref->update(blocks, &dxr, &nisr), Status::kOk) << where;
      ASSERT_LE(relDiff(dxt, dxr), tol) << where;
      ASSERT_NEAR(nist, nisr, tol * nisr) << where;
      ++counts->updates;
    }
    // Removals (the least recently added or random, 1 in 4 frames), then additions.
    if (K > 30 && r.i(0, 3) == 0) {
      const std::vector<int> slots = r.distinct(K, r.i(1, 5));
      ASSERT_EQ(test->removeLandmarks(slots), Status::kOk);
      ASSERT_EQ(ref->removeLandmarks(slots), Status::kOk);
      const std::vector<int> old_slot = oldSlotOfNew(K, slots);
      std::vector<int> a2;
      for (int k : old_slot) a2.push_back(area_of[k]);
      area_of = a2;
      counts->removals += static_cast<int>(slots.size());
    }
    const int m = std::min(cap - test->numLandmarks(), r.i(0, 4));
    if (m > 0) add(m, area);
    // The frame's last call: deferred work (background flush shares) starts
    // here and runs beside the next frame's prediction and pose read.
    ASSERT_EQ(test->frameCompleted(), Status::kOk) << where;
    ASSERT_EQ(ref->frameCompleted(), Status::kOk) << where;
    if (f % dense_every == dense_every - 1 || f == frames - 1) {
      ASSERT_EQ(test->numLandmarks(), ref->numLandmarks());
      ASSERT_LE(relDiff(test->denseCovariance(), ref->denseCovariance()), tol) << where;
      ASSERT_EQ(test->descriptors(), ref->descriptors()) << where;
      ++counts->checkpoints;
    }
  }
}

}  // namespace testing_sequence
}  // namespace hapi_eskf
