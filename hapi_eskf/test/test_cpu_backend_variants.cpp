// The CPU backend variants against each other on the same random sequences:
// OpenBLAS against Eigen (dense), and the partitioned update against the dense
// one (docs/DESIGN.md "Partitioned update"), to the 1e-9 relative of the GPU
// parity tests. Sequences have spatial structure: landmarks belong to areas,
// each frame observes its current area, the area switches, landmarks are
// added in the current area and removed anywhere (also active and basis ones).
#include "hapi_eskf/covariance_backend.hpp"
#include "hapi_eskf/removal_plan.hpp"
#include "hapi_eskf/so3.hpp"
#include "test_random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;
using testing_random::Rng;
using testing_random::randomBlock;
using testing_random::randomNewBlock;

double relDiff(const MatX& a, const MatX& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return 1e300;
  if (a.size() == 0) return 0.0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

PoseMat randomF(Rng& r, int P) {
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
void runSequence(CovarianceBackend* test, CovarianceBackend* ref, unsigned seed, int frames, int dense_every,
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
    if (f % dense_every == dense_every - 1 || f == frames - 1) {
      ASSERT_EQ(test->numLandmarks(), ref->numLandmarks());
      ASSERT_LE(relDiff(test->denseCovariance(), ref->denseCovariance()), tol) << where;
      ASSERT_EQ(test->descriptors(), ref->descriptors()) << where;
      ++counts->checkpoints;
    }
  }
}

TEST(CpuBackendVariants, BlasEqualsEigen) {
  if (std::string(makeCpuBackend(1, 0)->name()).find("blas") == std::string::npos) GTEST_SKIP() << "built without OpenBLAS";
  for (int P : {kCameraMotionDim, kMaxPoseDim}) {
    auto blas = makeCpuBackend(90, 8, P, CpuLinearAlgebra::kBlas);
    auto eigen = makeCpuBackend(90, 8, P, CpuLinearAlgebra::kEigen);
    EXPECT_STREQ(blas->name(), "cpu-blas");
    EXPECT_STREQ(eigen->name(), "cpu-eigen");
    Counts c;
    runSequence(blas.get(), eigen.get(), 21 + P, 150, 10, P, &c);
    EXPECT_GT(c.updates, 100);
    EXPECT_GT(c.removals, 0);
  }
}

TEST(CpuBackendVariants, PartitionedEqualsDenseOverLongSequences) {
  for (CpuLinearAlgebra la : {CpuLinearAlgebra::kBlas, CpuLinearAlgebra::kEigen}) {
    for (int P : {kCameraMotionDim, kMaxPoseDim}) {
      // max_active 30: the active part fills up and is flushed many times.
      auto part = makePartitionedCpuBackend(100, 8, P, la, 30);
      auto dense = makeCpuBackend(100, 8, P, la);
      ASSERT_TRUE(part && dense);
      Counts c;
      // Whole C only every 100 frames: in between the deferred part grows
      // as it does in the filter (a read-back of C flushes).
      runSequence(part.get(), dense.get(), 31 + P, 300, 100, P, &c);
      int flushes = 0;
      double seconds = 0;
      ASSERT_TRUE(partitionedFlushStats(*part, &flushes, &seconds));
      EXPECT_GT(flushes, 10) << "the sequence must exercise flushes";
      EXPECT_GT(c.switches, 20);
      EXPECT_GT(c.removals, 50);
      EXPECT_GT(c.updates, 250);
      EXPECT_FALSE(partitionedFlushStats(*dense, &flushes, &seconds));
    }
  }
}

// A large active budget: flushes only where the view jumps (an update with
// mostly passive landmarks) and at the final read-back, so long epochs with
// stray observations from other areas and removals of passive landmarks
// carry the deferred correction.
TEST(CpuBackendVariants, PartitionedLongEpochEqualsDense) {
  auto part = makePartitionedCpuBackend(150, 8, kCameraMotionDim, CpuLinearAlgebra::kBlas, 1000);
  auto dense = makeCpuBackend(150, 8, kCameraMotionDim, CpuLinearAlgebra::kBlas);
  Counts c;
  runSequence(part.get(), dense.get(), 41, 300, 1000, kCameraMotionDim, &c);
  int flushes = 0;
  double seconds = 0;
  ASSERT_TRUE(partitionedFlushStats(*part, &flushes, &seconds));
  EXPECT_GE(c.checkpoints, 1);
}

TEST(CpuBackendVariants, FactoryPicksTheVariant) {
  EskfSettings s;
  s.max_landmarks = 200;
  std::string err;
  auto b = makeBackend(s, 32, &err);
  ASSERT_TRUE(b) << err;
  EXPECT_STREQ(b->name(), makeCpuBackend(1, 0)->name());
  s.cpu_linear_algebra = CpuLinearAlgebra::kEigen;
  b = makeBackend(s, 32, &err);
  ASSERT_TRUE(b) << err;
  EXPECT_STREQ(b->name(), "cpu-eigen");
  s.covariance_update = CovarianceUpdate::kPartitioned;
  b = makeBackend(s, 32, &err);
  ASSERT_TRUE(b) << err;
  EXPECT_STREQ(b->name(), "cpu-eigen-partitioned");
  s.backend = BackendKind::kCuda;
  err.clear();
  EXPECT_FALSE(makeBackend(s, 32, &err));
  EXPECT_FALSE(err.empty());
}

}  // namespace
}  // namespace hapi_eskf
