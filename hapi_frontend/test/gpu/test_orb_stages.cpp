// Stage-level check of the FAST-9 score kernel: the full score map of one
// level against a brute-force evaluation of the definition used by
// OrbCpuCore (orb_core.cpp). The end-to-end identity test says *that* the
// keypoints differ; this one says whether the score map is the cause (it was:
// a ptxas fusion dropped a negation, see fastKernel). Skips without a device.
#include "hapi_frontend/cuda/orb_cuda.hpp"
#include "hapi_frontend/orb_core.hpp"

#include "../../src/cuda/orb_kernels.cuh"
#include "frames.hpp"
#include "hapi_test/skip.hpp"

#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace hapi_frontend {
namespace {

// FAST-9 score as defined in orb_core.cpp: largest b such that 9 contiguous
// circle pixels are all brighter than c + b or all darker than c - b; zero
// when not above the threshold or outside [edge-1, w-edge] x [edge-1, h-edge].
std::vector<uint8_t> referenceScores(const gpu_test::Frame& f, int t, int edge) {
  static const int dx[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
  static const int dy[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};
  const int w = f.width, h = f.height;
  std::vector<uint8_t> s(static_cast<size_t>(w) * h, 0);
  for (int y = edge - 1; y <= h - edge; ++y)
    for (int x = edge - 1; x <= w - edge; ++x) {
      const int c = f.pixels[static_cast<size_t>(y) * w + x];
      int best = 0;
      for (int k = 0; k < 16; ++k) {
        int lo = 255, hi = -255;
        for (int j = 0; j < 9; ++j) {
          const int i = (k + j) % 16;
          const int v = f.pixels[static_cast<size_t>(y + dy[i]) * w + x + dx[i]] - c;
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
        best = std::max(best, std::max(lo, -hi));
      }
      s[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>(best > t ? best : 0);
    }
  return s;
}

TEST(OrbCudaStages, FastScoreMapEqualsDefinition) {
  std::string info;
  if (!cudaDeviceAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  const int w = 640, h = 480, edge = 19;
  int total_diff = 0, total_nonzero = 0;
  for (int t : {7, 20}) {
    for (uint32_t seed : {100u, 101u}) {
      gpu_test::Frame l, r;
      gpu_test::renderStereoPair(w, h, seed, 48, 3, l, r);
      const std::vector<uint8_t> ref = referenceScores(l, t, edge);
      uint8_t *d_img = nullptr, *d_score = nullptr;
      unsigned long long* d_keys = nullptr;
      int* d_count = nullptr;
      const size_t n = static_cast<size_t>(w) * h;
      ASSERT_EQ(cudaMalloc(&d_img, n), cudaSuccess);
      ASSERT_EQ(cudaMalloc(&d_score, n), cudaSuccess);
      ASSERT_EQ(cudaMalloc(&d_keys, n / 4 * sizeof(unsigned long long)), cudaSuccess);
      ASSERT_EQ(cudaMalloc(&d_count, sizeof(int)), cudaSuccess);
      ASSERT_EQ(cudaMemcpy(d_img, l.pixels.data(), n, cudaMemcpyHostToDevice), cudaSuccess);
      ASSERT_EQ(cudaMemset(d_score, 0xCD, n), cudaSuccess);  // every pixel must be written
      ASSERT_EQ(cudaMemset(d_count, 0, sizeof(int)), cudaSuccess);
      orb_cuda::launchFastNms(d_img, d_score, w, h, t, edge, 0, d_keys, d_count, nullptr);
      ASSERT_EQ(cudaDeviceSynchronize(), cudaSuccess);
      std::vector<uint8_t> got(n);
      ASSERT_EQ(cudaMemcpy(got.data(), d_score, n, cudaMemcpyDeviceToHost), cudaSuccess);
      cudaFree(d_img);
      cudaFree(d_score);
      cudaFree(d_keys);
      cudaFree(d_count);
      int diff = 0, nonzero = 0, shown = 0;
      for (size_t i = 0; i < n; ++i) {
        nonzero += ref[i] != 0;
        if (ref[i] != got[i]) {
          ++diff;
          if (shown++ < 3)
            std::printf("[ fast ] t=%d seed=%u (%zu,%zu): reference %d, GPU %d\n", t, seed, i % w, i / w, ref[i],
                        got[i]);
        }
      }
      std::printf("[ fast ] t=%d seed=%u: %d of %zu score pixels differ (%d non-zero)\n", t, seed, diff, n, nonzero);
      total_diff += diff;
      total_nonzero += nonzero;
    }
  }
  EXPECT_GT(total_nonzero, 1000);  // not vacuous: many corners above threshold
  EXPECT_EQ(total_diff, 0);
}

}  // namespace
}  // namespace hapi_frontend
