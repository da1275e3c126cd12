// ImageFlowTracker on rendered textures with a known flow: sub-pixel
// translation, an affine warp's gradient, a blank image, restarts, input
// errors, and the covariance against the actual error over noisy trials.
#include "flow_texture.hpp"

#include "hapi_frontend/image_flow_tracker.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

namespace hapi_frontend {
namespace {

using hapi_frontend_test::WaveTexture;
constexpr int kW = 240, kH = 200;
constexpr std::int64_t kFrameNs = 25'000'000;  // 40 Hz
const double kCu = 0.5 * (kW - 1), kCv = 0.5 * (kH - 1);

// Two frames: the texture, then the texture moved by `a`; the second result.
ImageFlowResult flowOf(const WaveTexture& tex, const double a[6], const ImageFlowParams& p = ImageFlowParams(),
                       double noise = 0, std::mt19937* rng = nullptr) {
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  ImageFlowTracker tracker(p);
  ImageFlowResult r;
  EXPECT_FALSE(tracker.process(tex.renderAffine(kW, kH, kCu, kCv, zero, noise, rng), 1'000'000'000, &r));
  EXPECT_EQ(r.status, FlowStatus::kFirstFrame);
  EXPECT_FALSE(tracker.process(tex.renderAffine(kW, kH, kCu, kCv, a, noise, rng), 1'000'000'000 + kFrameNs, &r));
  return r;
}

TEST(ImageFlowTracker, SubPixelTranslationWithinTwoHundredthsOfAPixel) {
  const WaveTexture tex(7);
  const double shifts[][2] = {{0.25, -0.4}, {1.3, 0.7}, {-2.6, 1.85}, {0.05, 0.0}, {4.4, -3.2}};
  for (const auto& s : shifts) {
    const double a[6] = {s[0], s[1], 0, 0, 0, 0};
    const ImageFlowResult r = flowOf(tex, a);
    ASSERT_EQ(r.status, FlowStatus::kOk) << s[0] << ", " << s[1];
    EXPECT_NEAR(r.affine(0), s[0], 0.02) << "shift " << s[0] << ", " << s[1];
    EXPECT_NEAR(r.affine(1), s[1], 0.02) << "shift " << s[0] << ", " << s[1];
    for (int i = 2; i < 6; ++i) EXPECT_NEAR(r.affine(i), 0.0, 1e-3) << "gradient " << i;
    EXPECT_GE(r.inliers, 40u);
    EXPECT_LE(r.inliers, r.tracked);
    EXPECT_DOUBLE_EQ(r.u, kCu);
    EXPECT_DOUBLE_EQ(r.v, kCv);
  }
}

TEST(ImageFlowTracker, AffineWarpRecoversTheGradient) {
  const WaveTexture tex(11);
  // Stretch, shear and rotation of about 1 % per frame plus a translation.
  const double a[6] = {0.8, -0.55, 0.012, -0.015, 0.009, -0.01};
  const ImageFlowResult r = flowOf(tex, a);
  ASSERT_EQ(r.status, FlowStatus::kOk);
  EXPECT_NEAR(r.affine(0), a[0], 0.02);
  EXPECT_NEAR(r.affine(1), a[1], 0.02);
  for (int i = 2; i < 6; ++i) EXPECT_NEAR(r.affine(i), a[i], 1e-3) << "gradient parameter " << i;
}

TEST(ImageFlowTracker, FlowIsAboutTheConfiguredPixel) {
  // The same warp about another pixel: the flow there is t + G (p - c).
  const WaveTexture tex(13);
  const double a[6] = {0.5, 0.3, 0.01, 0.0, 0.0, 0.01};
  ImageFlowParams p;
  p.u = 70;
  p.v = 60;
  p.search_radius = 40;
  const ImageFlowResult r = flowOf(tex, a, p);
  ASSERT_EQ(r.status, FlowStatus::kOk);
  EXPECT_NEAR(r.affine(0), a[0] + a[2] * (70 - kCu), 0.02);
  EXPECT_NEAR(r.affine(1), a[1] + a[5] * (60 - kCv), 0.02);
  EXPECT_DOUBLE_EQ(r.u, 70);
  EXPECT_DOUBLE_EQ(r.v, 60);
}

TEST(ImageFlowTracker, ForwardBackwardCheckDropsTracksThatDoNotReturn) {
  // In the second frame a square next to the pixel shows another part of
  // the texture: its corners find some match forwards but do not come back.
  const WaveTexture tex(37);
  auto frame = [&](double dx, bool swapped) {
    return tex.render(kW, kH, [&](int x, int y, double* sx, double* sy) {
      const bool inside = swapped && x > kCu - 40 && x < kCu && y > kCv && y < kCv + 40;
      *sx = x - dx;
      *sy = inside ? y + 300 : y;
    });
  };
  auto run = [&](double fb_threshold) {
    ImageFlowParams p;
    p.fb_threshold = fb_threshold;
    ImageFlowTracker tracker(p);
    ImageFlowResult r;
    EXPECT_FALSE(tracker.process(frame(0, false), 1'000'000'000, &r));
    EXPECT_FALSE(tracker.process(frame(0.7, true), 1'000'000'000 + kFrameNs, &r));
    return r;
  };
  const ImageFlowResult checked = run(ImageFlowParams().fb_threshold), unchecked = run(1e6);
  ASSERT_EQ(checked.status, FlowStatus::kOk);
  EXPECT_EQ(checked.tracked, unchecked.tracked);
  EXPECT_LE(checked.inliers, checked.consistent);
  EXPECT_LE(checked.consistent + 10, unchecked.consistent) << "the check dropped (almost) nothing";
  EXPECT_NEAR(checked.affine(0), 0.7, 0.02);
  EXPECT_NEAR(checked.affine(1), 0.0, 0.02);
}

TEST(ImageFlowTracker, OccluderMovingOtherwiseIsIgnored) {
  // A textured occluder that moves differently covers a quarter of the
  // search square: the flow of the background is still measured.
  const WaveTexture tex(17);
  const double a[6] = {1.2, -0.7, 0, 0, 0, 0};
  auto frame = [&](double dx, double dy, double ox) {
    return tex.render(kW, kH, [&](int x, int y, double* sx, double* sy) {
      const bool occluder = x > kCu + 5 && x < kCu + 45 && y > kCv - 45 && y < kCv - 5;
      *sx = occluder ? x - ox : x - dx;
      *sy = occluder ? y + 500 : y - dy;  // the occluder shows another part of the texture
    });
  };
  ImageFlowTracker tracker{ImageFlowParams()};
  ImageFlowResult r;
  ASSERT_FALSE(tracker.process(frame(0, 0, 0), 1'000'000'000, &r));
  ASSERT_FALSE(tracker.process(frame(a[0], a[1], -3.0), 1'000'000'000 + kFrameNs, &r));
  ASSERT_EQ(r.status, FlowStatus::kOk);
  EXPECT_NEAR(r.affine(0), a[0], 0.03);
  EXPECT_NEAR(r.affine(1), a[1], 0.03);
  EXPECT_LT(r.inliers, r.tracked);
}

TEST(ImageFlowTracker, BlankImageGivesTooFewFeatures) {
  ImageFlowTracker tracker{ImageFlowParams()};
  const cv::Mat blank(kH, kW, CV_8UC1, cv::Scalar(90));
  ImageFlowResult r;
  ASSERT_FALSE(tracker.process(blank, 1'000'000'000, &r));
  EXPECT_EQ(r.status, FlowStatus::kFirstFrame);
  ASSERT_FALSE(tracker.process(blank, 1'000'000'000 + kFrameNs, &r));
  EXPECT_EQ(r.status, FlowStatus::kTooFewFeatures);
  EXPECT_EQ(r.tracked, 0u);
  EXPECT_EQ(r.inliers, 0u);
  EXPECT_TRUE(r.affine.isZero());
  EXPECT_TRUE(r.covariance.isZero());
}

TEST(ImageFlowTracker, StampsOutOfOrderEqualOrAfterAGapRestart) {
  const WaveTexture tex(23);
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  const cv::Mat img = tex.renderAffine(kW, kH, kCu, kCv, zero);
  ImageFlowParams p;
  p.max_gap = 0.1;
  ImageFlowTracker tracker(p);
  ImageFlowResult r;
  const std::int64_t t0 = 5'000'000'000;
  struct Step {
    std::int64_t t;
    FlowStatus status;
    const char* reason;
  };
  const Step steps[] = {{t0, FlowStatus::kFirstFrame, "start"},
                        {t0 + kFrameNs, FlowStatus::kOk, ""},
                        {t0, FlowStatus::kFirstFrame, "stamp_not_increasing"},  // backwards
                        {t0 + kFrameNs, FlowStatus::kOk, ""},
                        {t0 + kFrameNs, FlowStatus::kFirstFrame, "stamp_not_increasing"},  // repeated
                        {t0 + 2 * kFrameNs, FlowStatus::kOk, ""},
                        {t0 + 2 * kFrameNs + 100'000'001, FlowStatus::kFirstFrame, "gap"},
                        {t0 + 2 * kFrameNs + 200'000'001, FlowStatus::kOk, ""}};  // exactly max_gap: kept
  std::int64_t previous = 0;
  for (const Step& s : steps) {
    ASSERT_FALSE(tracker.process(img, s.t, &r));
    EXPECT_EQ(r.status, s.status) << "stamp " << s.t;
    EXPECT_EQ(r.restart_reason, s.reason) << "stamp " << s.t;
    EXPECT_EQ(r.stamp_ns, s.t);
    EXPECT_EQ(r.previous_stamp_ns, previous);
    if (s.status == FlowStatus::kOk) EXPECT_NEAR(r.affine.head<2>().norm(), 0.0, 0.01);
    previous = s.t;
  }
  tracker.reset();
  ASSERT_FALSE(tracker.process(img, t0 + 10 * kFrameNs, &r));
  EXPECT_EQ(r.status, FlowStatus::kFirstFrame);
}

TEST(ImageFlowTracker, BadFramesAreErrorsNotCrashes) {
  ImageFlowParams p;
  p.u = 300;  // beyond a 240 px wide image
  p.v = 10;
  ImageFlowTracker outside(p);
  ImageFlowResult r;
  const cv::Mat img(kH, kW, CV_8UC1, cv::Scalar(0));
  EXPECT_EQ(outside.process(img, 1, &r).reason, "pixel_outside_image");
  EXPECT_EQ(outside.process(cv::Mat(400, 400, CV_8UC1, cv::Scalar(0)), 2, &r).reason, "");

  ImageFlowTracker tracker{ImageFlowParams()};
  EXPECT_EQ(tracker.process(cv::Mat(), 1, &r).reason, "malformed_image");
  EXPECT_EQ(tracker.process(cv::Mat(kH, kW, CV_16UC1, cv::Scalar(0)), 1, &r).reason, "malformed_image");
  const WaveTexture tex(29);
  const double zero[6] = {0, 0, 0, 0, 0, 0};
  ASSERT_FALSE(tracker.process(tex.renderAffine(kW, kH, kCu, kCv, zero), kFrameNs, &r));
  const InputError e = tracker.process(tex.renderAffine(kW + 20, kH, kCu, kCv, zero), 2 * kFrameNs, &r);
  EXPECT_EQ(e.reason, "size_changed");
  EXPECT_EQ(r.status, FlowStatus::kFirstFrame);
  EXPECT_EQ(r.restart_reason, "size_changed");
  // The new size is the reference from now on (its centre is the pixel).
  ASSERT_FALSE(tracker.process(tex.renderAffine(kW + 20, kH, kCu, kCv, zero), 3 * kFrameNs, &r));
  EXPECT_EQ(r.status, FlowStatus::kOk);
  EXPECT_DOUBLE_EQ(r.u, 0.5 * (kW + 19));
  // Tiny images: no features, no crash.
  ImageFlowTracker tiny{ImageFlowParams()};
  ASSERT_FALSE(tiny.process(cv::Mat(1, 1, CV_8UC1, cv::Scalar(3)), 1, &r));
  ASSERT_FALSE(tiny.process(cv::Mat(1, 1, CV_8UC1, cv::Scalar(3)), 2, &r));
  EXPECT_EQ(r.status, FlowStatus::kTooFewFeatures);
}

TEST(ImageFlowTracker, InvalidSettingsAreRefused) {
  ImageFlowParams p;
  p.lk_window = 20;
  EXPECT_THROW(ImageFlowTracker{p}, std::invalid_argument);
  p = ImageFlowParams();
  p.min_inliers = 200;
  p.max_features = 100;
  EXPECT_NE(p.validate().find("min_inliers"), std::string::npos);
  p = ImageFlowParams();
  p.u = -2;
  EXPECT_NE(p.validate().find("u must be"), std::string::npos);
  EXPECT_EQ(ImageFlowParams().validate(), "");
}

// The covariance against the actual error: over noisy trials with random
// sub-pixel flows, the normalised error squared of the flow at the pixel
// (2 dof) and of all six parameters average to their dimensions.
TEST(ImageFlowTracker, CovarianceMatchesTheErrorOverNoisyTrials) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> shift(-2.0, 2.0), grad(-0.01, 0.01);
  const int trials = 120;
  double nees2 = 0, nees6 = 0;
  int ok = 0;
  for (int k = 0; k < trials; ++k) {
    const WaveTexture tex(1000 + k);
    const double a[6] = {shift(rng), shift(rng), grad(rng), grad(rng), grad(rng), grad(rng)};
    const ImageFlowResult r = flowOf(tex, a, ImageFlowParams(), 3.0, &rng);
    if (r.status != FlowStatus::kOk) continue;
    ++ok;
    Eigen::Matrix<double, 6, 1> e;
    for (int i = 0; i < 6; ++i) e(i) = r.affine(i) - a[i];
    nees2 += e.head<2>().dot(r.covariance.topLeftCorner<2, 2>().ldlt().solve(e.head<2>()));
    nees6 += e.dot(r.covariance.ldlt().solve(e));
  }
  ASSERT_EQ(ok, trials);
  nees2 /= ok;
  nees6 /= ok;
  // 95 % band of the mean of `trials` chi-square samples, widened by a
  // factor 1.5 for the heavier-than-Gaussian LK errors.
  EXPECT_GT(nees2, 2.0 / 1.5) << "covariance too large";
  EXPECT_LT(nees2, 2.0 * 1.5) << "covariance too small";
  EXPECT_GT(nees6, 6.0 / 1.5) << "covariance too large";
  EXPECT_LT(nees6, 6.0 * 1.5) << "covariance too small";
  std::printf("NEES over %d noisy trials: flow at the pixel %.2f (2 dof), all six %.2f (6 dof)\n", ok, nees2, nees6);
}

// use_gpu: the CUDA backend where a device is usable (its agreement with the
// CPU: hapi_frontend_flow_gpu_test); elsewhere the CPU backend, saying why,
// with the CPU tracker's results exactly.
TEST(ImageFlowTracker, UseGpuWithoutADeviceRunsTheCpuAndSaysWhy) {
  ImageFlowParams p;
  p.use_gpu = true;
  ImageFlowTracker gpu(p);
  if (gpu.usingGpu()) GTEST_SKIP() << "a CUDA device is usable: " << gpu.backendStatus();
  EXPECT_NE(gpu.backendStatus().find("using the CPU"), std::string::npos) << gpu.backendStatus();
  ImageFlowTracker cpu{ImageFlowParams()};
  EXPECT_FALSE(cpu.usingGpu());
  const WaveTexture tex(23);
  const double zero[6] = {0, 0, 0, 0, 0, 0}, a[6] = {1.1, -0.6, 0.004, 0, 0, -0.003};
  ImageFlowResult rc, rg;
  for (const double* step : {zero, a}) {
    const cv::Mat f = tex.renderAffine(kW, kH, kCu, kCv, step);
    cpu.process(f, 1'000'000'000 + (step == a) * kFrameNs, &rc);
    gpu.process(f, 1'000'000'000 + (step == a) * kFrameNs, &rg);
  }
  ASSERT_EQ(rg.status, FlowStatus::kOk);
  EXPECT_EQ(rg.affine, rc.affine);
  EXPECT_EQ(rg.covariance, rc.covariance);
}

}  // namespace
}  // namespace hapi_frontend
