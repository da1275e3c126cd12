// Test helpers: random but well-posed backend inputs (Jacobians of the real
// models at random poses), and a driver that applies the same call to the
// CPU reference and the CUDA backend and compares their full states.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/covariance/cuda_backend.hpp"
#include "hapi_eskf/so3.hpp"
#include "../test_random.hpp"
#include "hapi_test/skip.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace gputest {

#define HAPI_REQUIRE_CUDA_DEVICE()                                      \
  do {                                                                  \
    std::string why_;                                                   \
    if (!cuda::deviceAvailable(0, &why_)) HAPI_SKIP_WITHOUT_GPU(why_);   \
  } while (0)

using testing_random::Rng;
using testing_random::randomBlock;
using testing_random::randomNewBlock;

inline PoseMat randomF(Rng& r, int P = kCameraMotionDim) {
  PoseMat F = PoseMat::Identity(P, P);
  for (int i = 0; i < P; ++i)
    for (int j = 0; j < P; ++j) F(i, j) += r.n(0.05);
  return F;
}

// max |a - b| / max |b| (1e-300 floor): the "relative" of the parity tests.
inline double relDiff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return 1e300;
  if (a.size() == 0) return 0.0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

// Full observable state of a backend.
struct Snapshot {
  Eigen::MatrixXd C;
  std::vector<uint8_t> desc;
  int K;
  explicit Snapshot(const CovarianceBackend& b) : C(b.denseCovariance()), desc(b.descriptors()), K(b.numLandmarks()) {}
  bool same(const CovarianceBackend& b) const {
    return b.numLandmarks() == K && b.descriptors() == desc && b.denseCovariance() == C;
  }
};

// Device-side settings of the CUDA backend under test (device 0).
inline EskfSettings cudaSettings(Precision p = Precision::kFp64, CudaRankUpdate rank = CudaRankUpdate::kAuto,
                                 CudaSolve solve = CudaSolve::kAuto) {
  EskfSettings s;
  s.precision = p;
  s.cuda_device = 0;
  s.cuda_rank_update = rank;
  s.cuda_solve = solve;
  return s;
}

// The same inputs into the Eigen reference and the CUDA backend.
struct BackendPair {
  std::unique_ptr<CovarianceBackend> cpu, gpu;
  int dlen;

  BackendPair(int capacity, int descriptor_length, const EskfSettings& gpu_settings = cudaSettings(),
              int pose_dim = kCameraMotionDim)
      : dlen(descriptor_length) {
    cpu = makeCpuBackend(capacity, descriptor_length, pose_dim);
    std::string err;
    gpu = cuda::makeCudaBackend(capacity, descriptor_length, pose_dim, gpu_settings, &err);
    EXPECT_TRUE(gpu != nullptr) << err;
  }

  // Random landmarks with fresh descriptors; both must accept them.
  void addRandom(Rng& r, int m, std::vector<std::vector<uint8_t>>* store = nullptr) {
    std::vector<std::vector<uint8_t>> local(m);
    std::vector<NewLandmarkBlock> blocks;
    for (int i = 0; i < m; ++i) {
      local[i] = r.bytes(dlen);
      blocks.push_back(randomNewBlock(r, local[i]));
    }
    ASSERT_EQ(cpu->addLandmarks(blocks), Status::kOk);
    ASSERT_EQ(gpu->addLandmarks(blocks), Status::kOk);
    if (store) store->insert(store->end(), local.begin(), local.end());
  }

  void expectStatesEqual(double tol, const char* where) const {
    ASSERT_EQ(cpu->numLandmarks(), gpu->numLandmarks()) << where;
    EXPECT_LE(relDiff(gpu->denseCovariance(), cpu->denseCovariance()), tol) << where;
    EXPECT_LE(relDiff(gpu->poseCovariance(), cpu->poseCovariance()), tol) << where;
    EXPECT_EQ(gpu->descriptors(), cpu->descriptors()) << where;
  }
};

}  // namespace gputest
}  // namespace hapi_eskf
