// The image flow's CUDA stage (FlowLkCuda) against the same functions run on
// the host (test/flow_lk_reference.hpp), OpenCV-free: on procedural frames
// moving sideways (a stereo pair's disparity), the corners must be the same
// pixels in the same order and every track must match to 1e-4 px (both
// sides do the same IEEE float operations in the same order and add the
// window sums exactly; the margin only absorbs a compiler's reordering).
// Three frames, so the second tracking runs from the pyramid kept on the
// device. Skips without a CUDA device (fails with HAPI_REQUIRE_GPU=1).
#include "hapi_frontend/cuda/flow_lk_cuda.hpp"
#include "hapi_frontend/cuda/orb_cuda.hpp"  // cudaDeviceAvailable

#include "flow_lk_reference.hpp"
#include "frames.hpp"
#include "hapi_test/skip.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hapi_frontend {
namespace {

namespace ref = flow_lk_reference;

TEST(FlowLkCudaIdentity, CornersAndTracksEqualTheHostFunctions) {
  std::string info;
  if (!cudaDeviceAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  // ImageFlowParams' defaults.
  FlowLkCudaSettings s;
  s.levels = 3;
  s.window = 21;
  s.iterations = 30;
  s.epsilon = 0.001;
  s.max_features = 120;
  s.quality = 0.005;
  s.min_distance = 5;
  gpu_test::Frame left, right;
  gpu_test::renderStereoPair(320, 240, 7, 6, 2, left, right);
  const int sx = 160 - 48, sy = 120 - 48, side = 97;
  flow_lk::LkSettings lk;
  lk.window = s.window;
  lk.iterations = s.iterations;
  lk.epsilon_sq = s.epsilon * s.epsilon;
  lk.max_level = flow_lk::pyramidLevels(left.width, left.height, s.window, s.levels) - 1;

  FlowLkCuda cuda(s);
  FlowLkTracks t;
  const gpu_test::Frame* frames[] = {&left, &right, &left};
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    const gpu_test::Frame& f = *frames[k];
    cuda.frame(ImageView8{f.pixels.data(), f.width, f.height, f.width}, sx, sy, side, side, k > 0, &t);
    if (k == 0) {
      EXPECT_TRUE(t.from.empty());
      continue;
    }
    const gpu_test::Frame& p = *frames[k - 1];
    const std::vector<float> corners = ref::corners(p.pixels.data(), p.width, p.height, sx, sy, side, side,
                                                    s.max_features, s.quality, s.min_distance);
    ASSERT_GE(corners.size(), 2u * 60);
    ASSERT_EQ(t.from, corners) << "frame " << k;
    const ref::Pyramid from = ref::build(p.pixels.data(), p.width, p.height, s.window, s.levels);
    const ref::Pyramid to = ref::build(f.pixels.data(), f.width, f.height, s.window, s.levels);
    const std::size_t n = corners.size() / 2;
    ASSERT_EQ(t.ahead.size(), 2 * n);
    ASSERT_EQ(t.back.size(), 2 * n);
    ASSERT_EQ(t.ok.size(), n);
    int ok = 0;
    for (std::size_t i = 0; i < n; ++i) {
      float ax = 0, ay = 0;
      const bool sa = ref::track(from, to, lk, corners[2 * i], corners[2 * i + 1], false, &ax, &ay);
      float bx = corners[2 * i], by = corners[2 * i + 1];
      const bool sb = ref::track(to, from, lk, t.ahead[2 * i], t.ahead[2 * i + 1], true, &bx, &by);
      EXPECT_EQ(t.ok[i] != 0, sa && sb) << "point " << i << ", frame " << k;
      ok += t.ok[i] != 0;
      const double da = std::hypot(t.ahead[2 * i] - ax, t.ahead[2 * i + 1] - ay);
      const double db = std::hypot(t.back[2 * i] - bx, t.back[2 * i + 1] - by);
      EXPECT_LT(da, 1e-4) << "forward, point " << i << ", frame " << k;
      EXPECT_LT(db, 1e-4) << "backward, point " << i << ", frame " << k;
      worst = std::max({worst, da, db});
    }
    EXPECT_GE(ok, static_cast<int>(0.8 * n)) << "most corners must track across a few pixels of disparity";
  }
  std::printf("largest CUDA - host difference of a track: %.3g px\n", worst);
}

}  // namespace
}  // namespace hapi_frontend
