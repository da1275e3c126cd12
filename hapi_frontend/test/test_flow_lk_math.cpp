// The arithmetic of the CUDA image-flow stage (flow_lk_math.hpp), run on the
// host, against the OpenCV calls of the CPU stage on textured windows: the LK
// pyramid and its derivatives bit for bit, the Shi-Tomasi eigenvalues to
// float rounding, the chosen corners, and pyramidal LK point by point. The
// kernels only apply these functions to every pixel or point
// (flow_lk_kernels.cu); hapi_frontend_flow_gpu_test checks them on a device.
#include "flow_lk_reference.hpp"
#include "flow_texture.hpp"

#include "hapi_frontend/cuda/flow_lk_math.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

namespace hapi_frontend {
namespace {

namespace ref = flow_lk_reference;

// A continuous window's pyramid as the CUDA stage builds it, on the host.
ref::Pyramid build(const cv::Mat& window, int window_side, int levels) {
  return ref::build(window.data, window.cols, window.rows, window_side, levels);
}

cv::Mat texturedWindow(unsigned seed, int w, int h, const double a[6]) {
  const hapi_frontend_test::WaveTexture tex(seed);
  return tex.renderAffine(w, h, 0.5 * (w - 1), 0.5 * (h - 1), a);
}

const double kStill[6] = {0, 0, 0, 0, 0, 0};

TEST(FlowLkMath, PyramidAndDerivativesEqualOpenCVsBitForBit) {
  // Odd and even sizes, and one whose third level would be too small.
  const int sizes[][2] = {{265, 265}, {200, 151}, {90, 64}};
  for (const auto& sz : sizes) {
    const cv::Mat win = texturedWindow(3, sz[0], sz[1], kStill);
    std::vector<cv::Mat> cv_pyr;
    const int top = cv::buildOpticalFlowPyramid(win, cv_pyr, cv::Size(21, 21), 2, true, cv::BORDER_REFLECT_101,
                                                cv::BORDER_CONSTANT, false);
    const ref::Pyramid ours = build(win, 21, 3);
    ASSERT_EQ(static_cast<int>(ours.levels.size()), top + 1) << sz[0] << "x" << sz[1];
    for (int l = 0; l <= top; ++l) {
      const flow_lk::Level& L = ours.levels[l];
      const cv::Mat img(L.height, L.width, CV_8UC1, const_cast<std::uint8_t*>(L.img));
      const cv::Mat deriv(L.height, L.width, CV_16SC2, const_cast<std::int16_t*>(L.deriv));
      EXPECT_EQ(cv::norm(img, cv_pyr[2 * l], cv::NORM_INF), 0.0) << "level " << l;
      EXPECT_EQ(cv::norm(deriv.reshape(1), cv_pyr[2 * l + 1].reshape(1), cv::NORM_INF), 0.0)
          << "derivatives of level " << l;
    }
  }
}

// goodFeaturesToTrack on the square of `win` through flow_lk_math, in
// square coordinates.
std::vector<cv::Point2f> ourCorners(const cv::Mat& win, const cv::Rect& sq, int max_features, double quality,
                                    double min_distance) {
  const std::vector<float> xy = ref::corners(win.data, win.cols, win.rows, sq.x, sq.y, sq.width, sq.height,
                                             max_features, quality, min_distance);
  std::vector<cv::Point2f> out;
  for (std::size_t k = 0; k < xy.size(); k += 2) out.emplace_back(xy[k] - sq.x, xy[k + 1] - sq.y);
  return out;
}

TEST(FlowLkMath, CornersAreGoodFeaturesToTracks) {
  for (unsigned seed : {3u, 8u, 21u}) {
    const cv::Mat win = texturedWindow(seed, 265, 265, kStill);
    const cv::Rect sq(84, 84, 97, 97);
    const std::vector<cv::Point2f> ours = ourCorners(win, sq, 120, 0.005, 5);
    const std::vector<float> eig = ref::eigenMap(win.data, win.cols, win.rows, sq.x, sq.y, sq.width, sq.height);
    cv::Mat cv_eig;
    cv::cornerMinEigenVal(win(sq), cv_eig, 3, 3);
    double max_eig = 0;
    cv::minMaxLoc(cv_eig, nullptr, &max_eig);
    for (int y = 0; y < sq.height; ++y)
      for (int x = 0; x < sq.width; ++x)
        ASSERT_NEAR(eig[y * sq.width + x], cv_eig.at<float>(y, x), 1e-5 * max_eig) << x << ", " << y;
    std::vector<cv::Point2f> theirs;
    cv::goodFeaturesToTrack(win(sq), theirs, 120, 0.005, 5);
    ASSERT_EQ(ours.size(), theirs.size()) << "seed " << seed;
    // Eigenvalues equal to rounding can swap two near-equal corners; nearly
    // all must be the same pixels in the same order.
    int same = 0;
    for (std::size_t i = 0; i < ours.size(); ++i) same += ours[i] == theirs[i];
    EXPECT_GE(same, static_cast<int>(0.95 * ours.size())) << "seed " << seed;
  }
}

TEST(FlowLkMath, TrackPointIsCalcOpticalFlowPyrLKs) {
  const double moves[][6] = {{0.6, -1.3, 0, 0, 0, 0}, {2.2, 1.7, 0.01, -0.008, 0.006, -0.012}, {-6.5, 4.1, 0, 0, 0, 0}};
  for (const auto& a : moves) {
    const cv::Mat w0 = texturedWindow(5, 265, 265, kStill), w1 = texturedWindow(5, 265, 265, a);
    const cv::Rect sq(84, 84, 97, 97);
    std::vector<cv::Point2f> from = ourCorners(w0, sq, 120, 0.005, 5);
    for (cv::Point2f& p : from) p += cv::Point2f(sq.tl());
    from.emplace_back(-30.f, 20.f);  // outside the window: lost by both
    const ref::Pyramid p0 = build(w0, 21, 3), p1 = build(w1, 21, 3);
    flow_lk::LkSettings s;
    s.window = 21;
    s.iterations = 30;
    s.max_level = static_cast<int>(p0.levels.size()) - 1;
    s.epsilon_sq = 0.001 * 0.001;
    std::vector<cv::Mat> c0, c1;
    cv::buildOpticalFlowPyramid(w0, c0, cv::Size(21, 21), 2, true, cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
    cv::buildOpticalFlowPyramid(w1, c1, cv::Size(21, 21), 2, true, cv::BORDER_REFLECT_101, cv::BORDER_CONSTANT, false);
    std::vector<cv::Point2f> ahead, back = from;
    std::vector<std::uint8_t> ok_a, ok_b;
    std::vector<float> err;
    const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.001);
    cv::calcOpticalFlowPyrLK(c0, c1, from, ahead, ok_a, err, cv::Size(21, 21), 2, stop);
    cv::calcOpticalFlowPyrLK(c1, c0, ahead, back, ok_b, err, cv::Size(21, 21), 2, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
    int agree = 0;
    for (std::size_t i = 0; i < from.size(); ++i) {
      float ax = 0, ay = 0, bx = from[i].x, by = from[i].y;
      const bool sa = ref::track(p0, p1, s, from[i].x, from[i].y, false, &ax, &ay);
      // Backwards from OpenCV's forward result, so each direction is compared alone.
      const bool sb = ref::track(p1, p0, s, ahead[i].x, ahead[i].y, true, &bx, &by);
      EXPECT_EQ(sa, ok_a[i] != 0) << "point " << i;
      EXPECT_EQ(sb, ok_b[i] != 0) << "point " << i;
      if (!sa || !ok_a[i]) continue;
      // OpenCV adds the window sums in float in its own order; ours are exact.
      const bool close = std::hypot(ax - ahead[i].x, ay - ahead[i].y) < 2e-3 &&
                         (!sb || std::hypot(bx - back[i].x, by - back[i].y) < 2e-3);
      agree += close;
    }
    EXPECT_GE(agree, static_cast<int>(0.97 * (from.size() - 1))) << "move " << a[0] << ", " << a[1];
    EXPECT_FALSE(ok_a.back());
  }
}

}  // namespace
}  // namespace hapi_frontend
