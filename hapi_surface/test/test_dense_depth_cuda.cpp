// The CUDA block matcher against its CPU reference, bit for bit (OpenCV-free,
// so it builds on the GPU machine; skips without a device, fails there with
// HAPI_REQUIRE_GPU=1).
#include "hapi_surface/cuda/dense_depth_cuda.hpp"

#include "hapi_test/skip.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace hapi_surface {
namespace {

// A w x h speckle (a 3x3 box blur of noise), and the same image shifted by
// d px (linear interpolation, replicated border): the right view of a plane.
struct Pair {
  int w, h;
  std::vector<std::uint8_t> left, right;
};

Pair makePair(int w, int h, double d, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> grey(0, 255);
  std::vector<int> noise(static_cast<std::size_t>(w) * h);
  for (int& v : noise) v = grey(rng);
  auto at = [&](int x, int y) {
    x = x < 0 ? 0 : (x >= w ? w - 1 : x);
    y = y < 0 ? 0 : (y >= h ? h - 1 : y);
    int s = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = std::min(std::max(x + dx, 0), w - 1), yy = std::min(std::max(y + dy, 0), h - 1);
        s += noise[static_cast<std::size_t>(yy) * w + xx];
      }
    return s / 9.0;
  };
  Pair p{w, h, std::vector<std::uint8_t>(noise.size()), std::vector<std::uint8_t>(noise.size())};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      p.left[static_cast<std::size_t>(y) * w + x] = static_cast<std::uint8_t>(std::lround(at(x, y)));
      const double u = x + d;
      const int u0 = static_cast<int>(std::floor(u));
      const double f = u - u0;
      p.right[static_cast<std::size_t>(y) * w + x] =
          static_cast<std::uint8_t>(std::lround((1 - f) * at(u0, y) + f * at(u0 + 1, y)));
    }
  return p;
}

TEST(BlockMatchCuda, EqualsCpuBitForBit) {
  if (!denseDepthCudaDevice()) HAPI_SKIP_WITHOUT_GPU("no CUDA device");
  const Pair pair = makePair(321, 203, 23.7, 5);  // odd sizes: partial thread blocks
  for (const BlockMatchParams& p : {BlockMatchParams{10, 32, 5, 10}, BlockMatchParams{0, 48, 9, 0}}) {
    std::vector<float> cpu(pair.left.size()), gpu(pair.left.size());
    blockMatchCpu(pair.left.data(), pair.right.data(), pair.w, pair.h, pair.w, p, cpu.data());
    blockMatchCuda(pair.left.data(), pair.right.data(), pair.w, pair.h, pair.w, p, gpu.data());
    ASSERT_EQ(std::memcmp(cpu.data(), gpu.data(), cpu.size() * sizeof(float)), 0) << "block " << p.block_size;
    // And the result is a disparity, not agreement on garbage.
    int near = 0;
    for (float v : cpu) near += std::abs(v - 23.7f) < 0.3f ? 1 : 0;
    EXPECT_GT(near, static_cast<int>(0.8 * cpu.size()));
  }
}

}  // namespace
}  // namespace hapi_surface
