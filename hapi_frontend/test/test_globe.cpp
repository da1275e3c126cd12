// The front end's accuracy criteria on rendered globe stereo pairs (hapi_sim),
// on frames along the sim trajectory that were NOT used to estimate the
// default pixel_sigma (those were t = 1.0 + 0.8 k, k < 30):
//  >= 150 landmarks per frame, median 3D error <= 1 % of depth,
//  mean landmark NEES within 3 +- 0.5, < 2 % wrong stereo matches.
#include "globe_eval.hpp"

#include <gtest/gtest.h>

using namespace hapi_frontend;
using namespace hapi_frontend::globe_eval;

namespace {
struct Summary {
  int frames = 0, landmarks = 0, wrong = 0, min_landmarks = 1 << 30;
  std::vector<double> rel, nees;
};

Summary runFrames(const PipelineParams& pp, const std::vector<double>& times, cv::Mat* last_colour = nullptr) {
  static const GlobeWorld w;
  StereoPipeline pipe(pp);
  EXPECT_EQ(pipe.setCalibration(copyCameraInfo(w.rig.leftInfo()), copyCameraInfo(w.rig.rightInfo())), "");
  Summary s;
  for (size_t f = 0; f < times.size(); ++f) {
    const GlobePair p = renderPair(w, times[f], 500 + static_cast<uint32_t>(f));
    StereoFrameResult r;
    cv::Mat colour;
    cv::cvtColor(p.left, colour, cv::COLOR_GRAY2BGR);
    EXPECT_EQ(pipe.process(p.left, p.right, colour, &r), "");
    EXPECT_EQ(r.descriptors.rows, static_cast<int>(r.landmarks.size()));
    for (size_t i = 1; i < r.landmarks.size(); ++i) EXPECT_GE(r.landmarks[i - 1].response, r.landmarks[i].response);
    const FrameStats fs = evaluate(w, p, r);
    ++s.frames;
    s.landmarks += fs.landmarks;
    s.wrong += fs.wrong;
    s.min_landmarks = std::min(s.min_landmarks, fs.landmarks);
    s.rel.insert(s.rel.end(), fs.rel_err.begin(), fs.rel_err.end());
    s.nees.insert(s.nees.end(), fs.nees.begin(), fs.nees.end());
    if (last_colour) *last_colour = colour;
  }
  return s;
}

std::vector<double> heldOutTimes() {
  std::vector<double> t;
  for (int k = 0; k < 12; ++k) t.push_back(0.37 + 1.9 * k);
  return t;
}
}  // namespace

TEST(GlobeAccuracy, OrbMeetsIssueCriteria) {
  PipelineParams pp;  // defaults: ORB, N = 200, refined, pixel_sigma 0.24
  const Summary s = runFrames(pp, heldOutTimes());
  const double wrong_pct = 100.0 * s.wrong / s.landmarks;
  std::printf("ORB: %d frames, min %d landmarks/frame, wrong %.2f %%, median err %.3f %% of depth, NEES mean %.2f\n",
              s.frames, s.min_landmarks, wrong_pct, 100 * median(s.rel), mean(s.nees));
  EXPECT_GE(s.min_landmarks, 150);
  EXPECT_LT(wrong_pct, 2.0);
  EXPECT_LE(median(s.rel), 0.01);
  EXPECT_NEAR(mean(s.nees), 3.0, 0.5);
}

// The NEES check can fail: a covariance scaled by a wrong sigma is caught.
TEST(GlobeAccuracy, NeesDetectsWrongPixelSigma) {
  PipelineParams pp;
  pp.pixel_sigma = 1.0;
  const Summary s = runFrames(pp, {2.0, 9.0});
  EXPECT_LT(mean(s.nees), 1.0);
}

TEST(GlobeAccuracy, AkazeAndDownscaleRunEndToEnd) {
  PipelineParams pp;
  pp.detector = "akaze";
  Summary s = runFrames(pp, {3.3, 11.1});
  std::printf("AKAZE: min %d landmarks/frame, wrong %d of %d, median err %.3f %%\n", s.min_landmarks, s.wrong,
              s.landmarks, 100 * median(s.rel));
  EXPECT_GE(s.min_landmarks, 100);
  EXPECT_LT(100.0 * s.wrong / s.landmarks, 2.0);
  EXPECT_LE(median(s.rel), 0.01);
  pp = PipelineParams();
  pp.downscale = 2.0;
  s = runFrames(pp, {3.3, 11.1});
  std::printf("ORB downscale 2: min %d landmarks/frame, wrong %d of %d, median err %.3f %%\n", s.min_landmarks,
              s.wrong, s.landmarks, 100 * median(s.rel));
  EXPECT_GE(s.min_landmarks, 100);
  EXPECT_LT(100.0 * s.wrong / s.landmarks, 2.0);
  EXPECT_LE(median(s.rel), 0.01);
}
