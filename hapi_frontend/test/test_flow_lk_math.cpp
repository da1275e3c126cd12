// The arithmetic of the CUDA image-flow stage (flow_lk_math.hpp), run on the
// host, against the OpenCV calls of the CPU stage on textured windows: the LK
// pyramid and its derivatives bit for bit, the Shi-Tomasi eigenvalues to
// float rounding, the chosen corners, and pyramidal LK point by point. The
// kernels only apply these functions to every pixel or point
// (flow_lk_kernels.cu); hapi_frontend_flow_gpu_test checks them on a device.
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

using flow_lk::Level;

// A window and its pyramid as the CUDA stage builds it, on the host.
struct HostPyramid {
  std::vector<cv::Mat> img, deriv;  // CV_8UC1, CV_16SC2 (continuous)
  std::vector<Level> levels;
};

HostPyramid build(const cv::Mat& window, int window_side, int levels) {
  HostPyramid p;
  const int n = flow_lk::pyramidLevels(window.cols, window.rows, window_side, levels);
  p.img.push_back(window.clone());
  for (int l = 1; l < n; ++l) {
    const cv::Mat& b = p.img.back();
    cv::Mat d((b.rows + 1) / 2, (b.cols + 1) / 2, CV_8UC1);
    for (int y = 0; y < d.rows; ++y)
      for (int x = 0; x < d.cols; ++x) d.at<std::uint8_t>(y, x) = flow_lk::pyrDownAt(b.data, b.cols, b.rows, x, y);
    p.img.push_back(d);
  }
  for (const cv::Mat& m : p.img) {
    cv::Mat d(m.rows, m.cols, CV_16SC2);
    for (int y = 0; y < m.rows; ++y)
      for (int x = 0; x < m.cols; ++x) {
        std::int16_t* o = d.ptr<std::int16_t>(y) + 2 * x;
        flow_lk::scharrAt(m.data, m.cols, m.rows, x, y, o, o + 1);
      }
    p.deriv.push_back(d);
    p.levels.push_back(Level{m.data, d.ptr<std::int16_t>(), m.cols, m.rows});
  }
  return p;
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
    const HostPyramid ours = build(win, 21, 3);
    ASSERT_EQ(static_cast<int>(ours.levels.size()), top + 1) << sz[0] << "x" << sz[1];
    for (int l = 0; l <= top; ++l) {
      EXPECT_EQ(cv::norm(ours.img[l], cv_pyr[2 * l], cv::NORM_INF), 0.0) << "level " << l;
      EXPECT_EQ(cv::norm(ours.deriv[l].reshape(1), cv_pyr[2 * l + 1].reshape(1), cv::NORM_INF), 0.0)
          << "derivatives of level " << l;
    }
  }
}

// goodFeaturesToTrack on the square of `win` through flow_lk_math.
std::vector<cv::Point2f> ourCorners(const cv::Mat& win, const cv::Rect& sq, int max_features, double quality,
                                    double min_distance, std::vector<float>* eig_out = nullptr) {
  std::vector<float> eig(static_cast<std::size_t>(sq.area()));
  float max = 0;
  for (int y = 0; y < sq.height; ++y)
    for (int x = 0; x < sq.width; ++x) {
      eig[y * sq.width + x] = flow_lk::minEigenAt(win.data, win.cols, win.rows, sq.x, sq.y, sq.width, sq.height, x, y);
      max = std::max(max, eig[y * sq.width + x]);
    }
  const float threshold = static_cast<float>(static_cast<double>(max) * quality);
  std::vector<flow_lk::Candidate> cand;
  for (int y = 0; y < sq.height; ++y)
    for (int x = 0; x < sq.width; ++x)
      if (flow_lk::isCandidate(eig.data(), sq.width, sq.height, x, y, threshold))
        cand.push_back(flow_lk::Candidate{eig[y * sq.width + x], y * sq.width + x});
  std::vector<float> xy;
  flow_lk::selectCorners(&cand, sq.width, max_features, min_distance, &xy);
  std::vector<cv::Point2f> out;
  for (std::size_t k = 0; k < xy.size(); k += 2) out.emplace_back(xy[k], xy[k + 1]);
  if (eig_out) *eig_out = eig;
  return out;
}

TEST(FlowLkMath, CornersAreGoodFeaturesToTracks) {
  for (unsigned seed : {3u, 8u, 21u}) {
    const cv::Mat win = texturedWindow(seed, 265, 265, kStill);
    const cv::Rect sq(84, 84, 97, 97);
    std::vector<float> eig;
    const std::vector<cv::Point2f> ours = ourCorners(win, sq, 120, 0.005, 5, &eig);
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
    const HostPyramid p0 = build(w0, 21, 3), p1 = build(w1, 21, 3);
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
    std::vector<std::int16_t> scratch(3 * 21 * 21);
    int agree = 0;
    for (std::size_t i = 0; i < from.size(); ++i) {
      float ax = 0, ay = 0, bx = from[i].x, by = from[i].y;
      const bool sa = flow_lk::trackPoint(flow_lk::SoloTeam(), p0.levels.data(), p1.levels.data(), s, from[i].x,
                                          from[i].y, false, &ax, &ay, scratch.data());
      // Backwards from OpenCV's forward result, so each direction is compared alone.
      const bool sb = flow_lk::trackPoint(flow_lk::SoloTeam(), p1.levels.data(), p0.levels.data(), s, ahead[i].x,
                                          ahead[i].y, true, &bx, &by, scratch.data());
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
