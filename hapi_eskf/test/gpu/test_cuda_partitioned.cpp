// The partitioned update on the CUDA backend (docs/DESIGN.md "Partitioned
// update", GPU variant), FP64: against the dense CPU backend and the
// partitioned CPU backend on the long random sequences of the CPU variant
// tests (area switches, additions, removals of active, basis and passive
// landmarks; dx, NIS and the next frame's marginals every frame, the whole C
// after every flushing read-back), and as a complete filter against the dense
// CPU filter (the frames of test_partitioned_filter.cpp). Every case skips
// without a CUDA device.
#include "backend_pair.hpp"
#include "../backend_sequence.hpp"
#include "../basic_settings.hpp"
#include "../partitioned_filter_run.hpp"

namespace hapi_eskf {
namespace gputest {
namespace {

using testing_sequence::Counts;
using testing_sequence::runSequence;

std::unique_ptr<CovarianceBackend> makeCudaPartitioned(int capacity, int pose_dim, int max_active,
                                                       int flush_shares = 1, bool background = false) {
  EskfSettings s = cudaSettings();
  s.covariance_update = CovarianceUpdate::kPartitioned;
  s.partition_max_active = max_active;
  s.partition_flush_shares = flush_shares;
  s.partition_flush_background = background;
  std::string err;
  auto b = cuda::makePartitionedCudaBackend(capacity, 8, pose_dim, s, &err);
  EXPECT_TRUE(b) << err;
  return b;
}

int flushesOf(const CovarianceBackend& b) {
  int flushes = 0;
  double seconds = 0;
  EXPECT_TRUE(partitionedFlushStats(b, &flushes, &seconds));
  return flushes;
}

TEST(CudaPartitioned, FactoryNamesAndRefusesFp32) {
  HAPI_REQUIRE_CUDA_DEVICE();
  auto b = makeCudaPartitioned(50, kCameraMotionDim, 30);
  ASSERT_TRUE(b);
  EXPECT_STREQ(b->name(), "cuda-fp64-partitioned");
  EXPECT_EQ(b->capacity(), 50);
  EskfSettings s = cudaSettings(Precision::kFp32);
  std::string err;
  EXPECT_FALSE(cuda::makePartitionedCudaBackend(50, 8, kCameraMotionDim, s, &err));
  EXPECT_FALSE(err.empty());
}

// max_active 30: the active part fills up and is flushed many times.
TEST(CudaPartitioned, EqualsDenseCpuOverLongSequences) {
  HAPI_REQUIRE_CUDA_DEVICE();
  for (int P : {kCameraMotionDim, cuda::kMaxCudaPoseDim}) {
    auto part = makeCudaPartitioned(100, P, 30);
    auto dense = makeCpuBackend(100, 8, P);
    ASSERT_TRUE(part && dense);
    Counts c;
    runSequence(part.get(), dense.get(), 31 + P, 300, 100, P, &c);
    if (HasFatalFailure()) return;
    EXPECT_GT(flushesOf(*part), 10) << "the sequence must exercise flushes";
    EXPECT_GT(c.switches, 20);
    EXPECT_GT(c.removals, 50);
    EXPECT_GT(c.updates, 250);
  }
}

// The same calls into the partitioned CPU and CUDA backends: the same
// representation and flush triggers, so the same results at every step.
TEST(CudaPartitioned, EqualsCpuPartitioned) {
  HAPI_REQUIRE_CUDA_DEVICE();
  for (int P : {kCameraMotionDim, cuda::kMaxCudaPoseDim}) {
    auto gpu = makeCudaPartitioned(100, P, 30);
    auto cpu = makePartitionedCpuBackend(100, 8, P, CpuLinearAlgebra::kBlas, 30, 1);
    ASSERT_TRUE(gpu && cpu);
    Counts c;
    runSequence(gpu.get(), cpu.get(), 51 + P, 300, 25, P, &c);
    if (HasFatalFailure()) return;
    EXPECT_EQ(flushesOf(*gpu), flushesOf(*cpu));
    EXPECT_GT(c.checkpoints, 10);
  }
}

// A staged CUDA backend (`shares`, shares in the background or not) against
// the dense CPU backend (seed) and against the CPU variant with the same
// settings and calls, hence the same flushes and shares (seed + 10).
void expectStagedEqualsDenseAndCpu(int shares, bool background, unsigned seed) {
  for (int P : {kCameraMotionDim, cuda::kMaxCudaPoseDim}) {
    SCOPED_TRACE("shares " + std::to_string(shares) + (background ? " background" : "") + ", P " +
                 std::to_string(P));
    auto gpu = makeCudaPartitioned(100, P, 30, shares, background);
    auto dense = makeCpuBackend(100, 8, P);
    ASSERT_TRUE(gpu && dense);
    Counts c;
    runSequence(gpu.get(), dense.get(), seed + P + shares, 300, 37, P, &c);
    if (::testing::Test::HasFatalFailure()) return;
    EXPECT_GT(flushesOf(*gpu), 10);
    EXPECT_GT(c.removals, 50);
    auto gpu2 = makeCudaPartitioned(100, P, 30, shares, background);
    auto cpu = makePartitionedCpuBackend(100, 8, P, CpuLinearAlgebra::kBlas, 30, shares, background);
    ASSERT_TRUE(gpu2 && cpu);
    runSequence(gpu2.get(), cpu.get(), seed + 10 + P + shares, 300, 25, P, &c);
    if (::testing::Test::HasFatalFailure()) return;
    EXPECT_EQ(flushesOf(*gpu2), flushesOf(*cpu));
  }
}

// Staged flushes (docs/DESIGN.md "Staged flush").
TEST(CudaPartitioned, StagedFlushEqualsDenseAndCpuStaged) {
  HAPI_REQUIRE_CUDA_DEVICE();
  for (int shares : {2, 5}) {
    expectStagedEqualsDenseAndCpu(shares, false, 51);
    if (HasFatalFailure()) return;
  }
}

// Background shares (docs/DESIGN.md "Background shares"): queued on the
// stream at the end of each frame.
TEST(CudaPartitioned, BackgroundSharesEqualDenseAndCpuBackground) {
  HAPI_REQUIRE_CUDA_DEVICE();
  for (int shares : {1, 3}) {
    expectStagedEqualsDenseAndCpu(shares, true, 71);
    if (HasFatalFailure()) return;
  }
}

TEST(CudaPartitioned, BackgroundSharesFilterMatchesDenseCpuFilter) {
  HAPI_REQUIRE_CUDA_DEVICE();
  EskfSettings s = testing_settings::basicFilter();
  s.partition_flush_shares = 2;
  s.partition_flush_background = true;
  testing_partitioned::runFilters(s, 150, 30, BackendKind::kCuda);
}

TEST(CudaPartitioned, StagedFlushFilterMatchesDenseCpuFilter) {
  HAPI_REQUIRE_CUDA_DEVICE();
  EskfSettings s = testing_settings::basicFilter();
  s.partition_flush_shares = 3;
  testing_partitioned::runFilters(s, 150, 30, BackendKind::kCuda);
}

// A large active budget: flushes only where the view jumps and at the final
// read-back, so long epochs carry the deferred correction.
TEST(CudaPartitioned, LongEpochEqualsDenseCpu) {
  HAPI_REQUIRE_CUDA_DEVICE();
  auto part = makeCudaPartitioned(150, kCameraMotionDim, 1000);
  auto dense = makeCpuBackend(150, 8, kCameraMotionDim);
  ASSERT_TRUE(part && dense);
  Counts c;
  runSequence(part.get(), dense.get(), 41, 300, 1000, kCameraMotionDim, &c);
  EXPECT_GE(c.checkpoints, 1);
}

TEST(CudaPartitioned, FilterMatchesDenseCpuFilter) {
  HAPI_REQUIRE_CUDA_DEVICE();
  testing_partitioned::runFilters(testing_settings::basicFilter(), 150, 30, BackendKind::kCuda);
}

TEST(CudaPartitioned, TunedFilterMatchesDenseCpuFilter) {
  HAPI_REQUIRE_CUDA_DEVICE();
  EskfSettings s;  // RANSAC, bootstrap batch, re-detection noise as shipped
  testing_partitioned::runFilters(s, 150, 50, BackendKind::kCuda);
}

}  // namespace
}  // namespace gputest
}  // namespace hapi_eskf
