// The CUDA backend of ImageFlowTracker against the CPU one (OpenCV) on the
// same rendered frames of a known motion (test/flow_texture.hpp): the
// stage's corners and tracks point by point, and the tracker's affine flow,
// equal within the stated tolerances and both within the known motion. Skips
// without a CUDA device (fails with HAPI_REQUIRE_GPU=1).
#include "flow_texture.hpp"

#include "hapi_frontend/cuda/orb_cuda.hpp"  // cudaDeviceAvailable
#include "hapi_frontend/flow_track_stage.hpp"
#include "hapi_frontend/image_flow_tracker.hpp"

#include "hapi_test/skip.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

namespace hapi_frontend {
namespace {

using hapi_frontend_test::WaveTexture;

// Both backends run OpenCV's arithmetic (flow_lk_math.hpp); what differs is
// the order of float sums (OpenCV's window sums and Sobel/box filters, exact
// int64 sums on the device): on the host the same functions stay within
// 2e-4 px of OpenCV per point (test_flow_lk_math.cpp). Allowed here: a track
// 2e-3 px, the flow at the pixel 3e-3 px, a gradient 3e-5 per frame; a
// near-tie of two corners' eigenvalues may swap them, so 95 % of the corners
// and 97 % of the tracks must agree, not all.
constexpr double kTrackTol = 2e-3;
constexpr double kFlowTol = 3e-3, kGradientTol = 3e-5;
// The known motion (as hapi_frontend_flow_test's CPU criteria).
constexpr double kTruthFlowTol = 0.02, kTruthGradientTol = 1e-3;

class FlowCuda : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string info;
    if (!cudaDeviceAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  }
};

cv::Mat frameOf(const WaveTexture& tex, int w, int h, const double a[6]) {
  return tex.renderAffine(w, h, 0.5 * (w - 1), 0.5 * (h - 1), a);
}

TEST_F(FlowCuda, StageTracksEqualTheCpuStagePointByPoint) {
  ImageFlowParams p;
  std::string status;
  std::unique_ptr<FlowTrackStage> gpu = makeCudaFlowStage(p, &status);
  ASSERT_TRUE(gpu) << status;
  std::unique_ptr<FlowTrackStage> cpu = makeCpuFlowStage(p);
  const WaveTexture tex(13);
  const double still[6] = {0, 0, 0, 0, 0, 0};
  const double moves[][6] = {{0.7, -1.2, 0, 0, 0, 0}, {2.4, 1.6, 0.011, -0.009, 0.007, -0.012}, {-6.2, 3.9, 0, 0, 0, 0}};
  const cv::Rect search(84, 84, 97, 97);  // the tracker's window about a pixel with the defaults
  FlowTracks tc, tg;
  cpu->frame(frameOf(tex, 265, 265, still), search, false, &tc);
  gpu->frame(frameOf(tex, 265, 265, still), search, false, &tg);
  EXPECT_TRUE(tc.from.empty() && tg.from.empty());
  for (const auto& a : moves) {
    const cv::Mat f = frameOf(tex, 265, 265, a);
    cpu->frame(f, search, true, &tc);
    gpu->frame(f, search, true, &tg);
    ASSERT_EQ(tg.from.size(), tc.from.size()) << "corners, move " << a[0];
    ASSERT_EQ(tg.ahead.size(), tg.from.size());
    ASSERT_EQ(tg.back.size(), tg.from.size());
    ASSERT_EQ(tg.ok.size(), tg.from.size());
    ASSERT_GE(tc.from.size(), 60u);
    int same = 0, agree = 0, ok = 0;
    for (std::size_t i = 0; i < tc.from.size(); ++i) {
      if (tg.from[i] != tc.from[i]) continue;
      ++same;
      ok += tc.ok[i] != 0;
      if ((tg.ok[i] != 0) != (tc.ok[i] != 0)) continue;
      if (!tc.ok[i]) {
        ++agree;
        continue;
      }
      agree += cv::norm(tg.ahead[i] - tc.ahead[i]) < kTrackTol && cv::norm(tg.back[i] - tc.back[i]) < kTrackTol;
    }
    EXPECT_GE(same, static_cast<int>(0.95 * tc.from.size())) << "move " << a[0];
    EXPECT_GE(agree, static_cast<int>(0.97 * same)) << "move " << a[0];
    EXPECT_GE(ok, static_cast<int>(0.9 * same)) << "most tracks must succeed, move " << a[0];
    // Going back to the still frame's texture must also agree: the
    // previous pyramid is the device's.
    cpu->frame(frameOf(tex, 265, 265, still), search, false, &tc);
    gpu->frame(frameOf(tex, 265, 265, still), search, false, &tg);
  }
}

TEST_F(FlowCuda, TrackerFlowEqualsTheCpuTrackersAndTheTruth) {
  ImageFlowParams p;
  ImageFlowParams pg = p;
  pg.use_gpu = true;
  ImageFlowTracker cpu(p), gpu(pg);
  ASSERT_TRUE(gpu.usingGpu()) << gpu.backendStatus();
  EXPECT_FALSE(cpu.usingGpu());
  const WaveTexture tex(17);
  constexpr int kW = 320, kH = 240;
  // A sequence of frames, each pair moved by a known affine flow about the
  // image centre (the tracker's pixel): every frame is rendered from the
  // previous one's motion so the flow between frames k-1 and k is a[k].
  const double flows[][6] = {{0.4, -0.3, 0, 0, 0, 0},
                             {1.3, 0.7, 0.008, -0.006, 0.005, -0.009},
                             {-2.6, 1.85, 0, 0, 0, 0},
                             {3.1, -2.2, -0.01, 0.012, -0.007, 0.011}};
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  std::int64_t t = 1'000'000'000;
  for (const auto& a : flows) {
    ImageFlowResult rc, rg;
    // Each flow is measured on its own pair: the reference frame, then the
    // texture moved by a (the tracker's sequence across pairs stays valid).
    for (const double* step : {zero, a}) {
      const cv::Mat f = frameOf(tex, kW, kH, step);
      EXPECT_FALSE(cpu.process(f, t, &rc));
      EXPECT_FALSE(gpu.process(f, t, &rg));
      t += 25'000'000;
    }
    ASSERT_EQ(rc.status, FlowStatus::kOk);
    ASSERT_EQ(rg.status, FlowStatus::kOk) << "flow " << a[0];
    EXPECT_NEAR(double(rg.tracked), double(rc.tracked), 0.05 * rc.tracked);
    EXPECT_NEAR(double(rg.inliers), double(rc.inliers), 0.05 * rc.inliers);
    for (int i = 0; i < 6; ++i) {
      const double tol = i < 2 ? kFlowTol : kGradientTol, truth = i < 2 ? kTruthFlowTol : kTruthGradientTol;
      EXPECT_NEAR(rg.affine(i), rc.affine(i), tol) << "CUDA vs CPU, parameter " << i << ", flow " << a[0];
      EXPECT_NEAR(rc.affine(i), a[i], truth) << "CPU vs truth, parameter " << i;
      EXPECT_NEAR(rg.affine(i), a[i], truth) << "CUDA vs truth, parameter " << i;
    }
    EXPECT_NEAR(rg.sigma, rc.sigma, 0.1 * rc.sigma + 1e-3);
  }
}

TEST_F(FlowCuda, RestartsAndSizeChangesAsTheCpuTracker) {
  ImageFlowParams pg;
  pg.use_gpu = true;
  ImageFlowTracker cpu{ImageFlowParams()}, gpu(pg);
  ASSERT_TRUE(gpu.usingGpu()) << gpu.backendStatus();
  const WaveTexture tex(19);
  const double a[6] = {0.9, -0.4, 0, 0, 0, 0}, zero[6] = {0, 0, 0, 0, 0, 0};
  // Frames: 320x240, moved, a smaller one (restart, the window is clipped
  // by the image), moved, a gap, moved.
  struct Step {
    int w, h;
    const double* a;
    std::int64_t dt;
  };
  const Step steps[] = {{320, 240, zero, 0}, {320, 240, a, 25}, {180, 150, zero, 25}, {180, 150, a, 25},
                        {180, 150, zero, 500}, {180, 150, a, 25}};
  std::int64_t t = 1'000'000'000;
  for (const Step& s : steps) {
    t += s.dt * 1'000'000;
    const cv::Mat f = frameOf(tex, s.w, s.h, s.a);
    ImageFlowResult rc, rg;
    const InputError ec = cpu.process(f, t, &rc), eg = gpu.process(f, t, &rg);
    EXPECT_EQ(eg.reason, ec.reason);
    EXPECT_EQ(rg.status, rc.status) << s.w << "x" << s.h << " at " << t;
    EXPECT_EQ(rg.restart_reason, rc.restart_reason);
    if (rc.status == FlowStatus::kOk && rg.status == FlowStatus::kOk) {
      EXPECT_NEAR(rg.affine(0), rc.affine(0), kFlowTol);
      EXPECT_NEAR(rg.affine(1), rc.affine(1), kFlowTol);
    }
  }
  EXPECT_TRUE(gpu.usingGpu());
}

}  // namespace
}  // namespace hapi_frontend
