// GPU faults of the CUDA backend (docs/RELIABILITY.md "GPU faults"): a pool
// that does not fit is refused with the memory needed and available; a CUDA
// error during a frame (the device's memory taken by someone else, so the
// frame's buffers cannot be allocated) is a Status::kBackendError with the
// failing call named, never a crash; the filter recovers on a new backend once
// the device has memory again, and BackendFaultPolicy's CPU fallback gives a
// running filter while it has not. Every case skips without a CUDA device.
#include "backend_pair.hpp"
#include "../basic_settings.hpp"

#include "hapi_eskf/covariance/backend_fault_policy.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"

#include <cuda_runtime.h>

#include <cstdio>
#include <random>

namespace hapi_eskf {
namespace gputest {
namespace {

// Takes (almost) all free device memory until destroyed.
class MemoryHog {
 public:
  MemoryHog() {
    for (std::size_t chunk : {std::size_t(1) << 30, std::size_t(64) << 20, std::size_t(2) << 20}) {
      void* p = nullptr;
      while (cudaMalloc(&p, chunk) == cudaSuccess) blocks_.push_back(p);
      cudaGetLastError();
    }
  }
  ~MemoryHog() {
    for (void* p : blocks_) cudaFree(p);
  }

 private:
  std::vector<void*> blocks_;
};

// Points 2-6 m in front of a static camera; `n` of them seen per frame.
StereoFrame frame(double stamp, int n) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  StereoFrame f;
  f.stamp = stamp;
  f.descriptor_length = 32;
  for (int i = 0; i < n; ++i) {
    StereoMeasurement m;
    m.z = Vec3(u(rng), u(rng), 4.0 + 2.0 * u(rng));
    m.Cz = 1e-4 * Mat3::Identity();
    m.frontend_id = static_cast<uint32_t>(i);
    m.response = static_cast<float>(n - i);
    f.measurements.push_back(m);
    for (int b = 0; b < 32; ++b) f.descriptors.push_back(static_cast<uint8_t>(rng()));
  }
  return f;
}

std::unique_ptr<Eskf> cudaFilter(const EskfSettings& s, std::string* err) {
  auto b = makeBackend(s, 32, err);
  if (!b) return nullptr;
  return std::make_unique<Eskf>(s, std::move(b));
}

EskfSettings faultSettings() {
  EskfSettings s = testing_settings::basicFilter();
  s.backend = BackendKind::kCuda;
  s.max_landmarks = 400;
  s.max_new_landmarks = 400;
  return s;
}

TEST(CudaFaults, APoolThatDoesNotFitIsRefusedWithTheMemoryFigures) {
  HAPI_REQUIRE_CUDA_DEVICE();
  EskfSettings s = faultSettings();
  s.max_landmarks = 200000;  // C alone: (12 + 600000)^2 doubles, 2.9 TB
  std::string why;
  EXPECT_FALSE(cudaPoolFits(s, 32, &why));
  EXPECT_NE(why.find("needs"), std::string::npos) << why;
  EXPECT_NE(why.find("free of"), std::string::npos) << why;
  std::string err;
  EXPECT_EQ(makeBackend(s, 32, &err), nullptr);
  EXPECT_NE(err.find("does not fit"), std::string::npos) << err;
  EXPECT_NE(err.find("MiB"), std::string::npos) << err;
  // A pool that fits is accepted by the same check.
  EXPECT_TRUE(cudaPoolFits(faultSettings(), 32, &why)) << why;
}

TEST(CudaFaults, ACudaErrorDuringAFrameIsReportedAndANewBackendRecovers) {
  HAPI_REQUIRE_CUDA_DEVICE();
  const EskfSettings s = faultSettings();
  std::string err;
  std::unique_ptr<Eskf> eskf = cudaFilter(s, &err);
  ASSERT_TRUE(eskf) << err;
  ASSERT_EQ(eskf->reset(PoseState(), 0.0), Status::kOk);
  ASSERT_EQ(eskf->processFrame(frame(0.0, 10)), Status::kOk);  // small buffers so far
  Status st = Status::kOk;
  {
    MemoryHog hog;
    // Many more matches than before: the update's buffers must grow, and the
    // device has no memory left for them.
    for (int i = 1; i <= 3 && st == Status::kOk; ++i) st = eskf->processFrame(frame(0.1 * i, 300));
    EXPECT_EQ(st, Status::kBackendError);
    EXPECT_FALSE(eskf->backend().lastError().empty());  // the failing call and CUDA's reason
    std::printf("CUDA error during the frame: %s\n", eskf->backend().lastError().c_str());
    // While the device is full no new backend can be created either.
    EXPECT_EQ(cudaFilter(s, &err), nullptr);
    EXPECT_FALSE(err.empty());
    // allow_cpu_fallback: the policy moves the filter to the CPU, which runs.
    EXPECT_EQ(BackendFaultPolicy(true).onCreateFailed(BackendKind::kCuda), FaultAction::kFallBackToCpu);
    EskfSettings cpu = s;
    cpu.backend = BackendKind::kCpu;
    std::unique_ptr<Eskf> fallback = cudaFilter(cpu, &err);
    ASSERT_TRUE(fallback) << err;
    ASSERT_EQ(fallback->reset(PoseState(), 1.0), Status::kOk);
    EXPECT_EQ(fallback->processFrame(frame(1.0, 300)), Status::kOk);
    EXPECT_EQ(fallback->processFrame(frame(1.1, 300)), Status::kOk);
  }
  // The device has memory again: a new CUDA backend runs the filter (restart).
  eskf.reset();
  eskf = cudaFilter(s, &err);
  ASSERT_TRUE(eskf) << err;
  ASSERT_EQ(eskf->reset(PoseState(), 2.0), Status::kOk);
  EXPECT_EQ(eskf->processFrame(frame(2.0, 300)), Status::kOk);
  EXPECT_EQ(eskf->processFrame(frame(2.1, 300)), Status::kOk);
  EXPECT_GT(eskf->numLandmarks(), 0);
  EXPECT_TRUE(eskf->pose().p.allFinite());
}

}  // namespace
}  // namespace gputest
}  // namespace hapi_eskf
