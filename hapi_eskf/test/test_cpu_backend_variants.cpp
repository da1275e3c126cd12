// The CPU backend variants against each other on the same random sequences:
// OpenBLAS against Eigen (dense), and the partitioned update against the dense
// one (docs/DESIGN.md "Partitioned update"), to the 1e-9 relative of the GPU
// parity tests, on the sequences of backend_sequence.hpp.
#include "backend_sequence.hpp"

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace {

using testing_sequence::Counts;
using testing_sequence::runSequence;

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
      auto part = makePartitionedCpuBackend(100, 8, P, la, 30, 1);
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

// A staged partitioned backend (`shares`, shares in the background or not)
// against the dense one on the long random sequences, for both pose blocks.
void expectStagedEqualsDense(int shares, bool background, unsigned seed) {
  for (int P : {kCameraMotionDim, kMaxPoseDim}) {
    SCOPED_TRACE("shares " + std::to_string(shares) + (background ? " background" : "") + ", P " +
                 std::to_string(P));
    auto part = makePartitionedCpuBackend(100, 8, P, CpuLinearAlgebra::kBlas, 30, shares, background);
    auto dense = makeCpuBackend(100, 8, P, CpuLinearAlgebra::kBlas);
    ASSERT_TRUE(part && dense);
    Counts c;
    runSequence(part.get(), dense.get(), seed + P + shares, 300, 37, P, &c);
    int flushes = 0;
    double seconds = 0;
    ASSERT_TRUE(partitionedFlushStats(*part, &flushes, &seconds));
    EXPECT_GT(flushes, 10) << "the sequence must exercise flushes";
    EXPECT_GT(c.removals, 50);
  }
}

// Staged flushes (docs/DESIGN.md "Staged flush"): the passive part of each
// flush pending over the next 2 or 5 updates, while joins and passive
// marginals read the stored C, removals move pending entries across the
// applied rows, and the next flush or a read-back finishes it early.
TEST(CpuBackendVariants, PartitionedStagedFlushEqualsDense) {
  for (int shares : {2, 5}) expectStagedEqualsDense(shares, false, 51);
  EXPECT_FALSE(makePartitionedCpuBackend(100, 8, kCameraMotionDim, CpuLinearAlgebra::kBlas, 30, 0));
}

// Background shares (docs/DESIGN.md "Background shares"): each share on the
// worker thread from the end of a frame, beside the next prediction and
// pose read, with one share (the whole passive product between two frames)
// and with three; the same sequences, the same bound.
TEST(CpuBackendVariants, PartitionedBackgroundSharesEqualDense) {
  for (int shares : {1, 3}) expectStagedEqualsDense(shares, true, 71);
}

// A large active budget: flushes only where the view jumps (an update with
// mostly passive landmarks) and at the final read-back, so long epochs with
// stray observations from other areas and removals of passive landmarks
// carry the deferred correction.
TEST(CpuBackendVariants, PartitionedLongEpochEqualsDense) {
  auto part = makePartitionedCpuBackend(150, 8, kCameraMotionDim, CpuLinearAlgebra::kBlas, 1000, 1);
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
  // The CUDA variant where a device is present (FP64 only), else a reason.
  s.backend = BackendKind::kCuda;
  err.clear();
  std::string why;
  b = makeBackend(s, 32, &err);
  if (cudaBackendAvailable(s.cuda_device, &why)) {
    ASSERT_TRUE(b) << err;
    EXPECT_STREQ(b->name(), "cuda-fp64-partitioned");
    s.precision = Precision::kFp32;
    err.clear();
    EXPECT_FALSE(makeBackend(s, 32, &err));
  } else {
    EXPECT_FALSE(b);
  }
  EXPECT_FALSE(err.empty());
}

}  // namespace
}  // namespace hapi_eskf
