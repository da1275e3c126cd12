// DenseDepth and StereoRectifier on synthetic pairs with known depth.
#include "hapi_surface/dense_depth.hpp"
#include "hapi_surface/dense_depth_rectifier.hpp"
#include "test_dense_depth_images.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_surface {
namespace {

using test_images::speckle;

// The right image of a left image seeing a surface of disparity d(u, v)
// (left pixel u appears at u - d(u) on the right): right(x) = left(u) with
// u - d(u) = x, solved by fixed-point iteration (|dd/du| < 1).
cv::Mat shiftedRight(const cv::Mat& left, const cv::Mat& disparity) {
  cv::Mat mx(left.size(), CV_32F), my(left.size(), CV_32F);
  for (int v = 0; v < left.rows; ++v)
    for (int x = 0; x < left.cols; ++x) {
      double u = x;
      for (int it = 0; it < 30; ++it) {
        const int ui = std::clamp(static_cast<int>(std::lround(u)), 0, left.cols - 1);
        const int u1 = std::min(ui + 1, left.cols - 1);
        const double f = u - ui;  // linear interpolation of d between texels
        const double d = (1 - f) * disparity.at<float>(v, ui) + f * disparity.at<float>(v, u1);
        u = x + d;
      }
      mx.at<float>(v, x) = static_cast<float>(u);
      my.at<float>(v, x) = static_cast<float>(v);
    }
  cv::Mat right;
  cv::remap(left, right, mx, my, cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return right;
}

RectifiedGeometry geometry(cv::Size size) {
  RectifiedGeometry g;
  g.fx = g.fy = 250.0;
  g.cx = size.width / 2.0;
  g.cy = size.height / 2.0;
  g.baseline = 0.06;
  g.width = size.width;
  g.height = size.height;
  return g;
}

struct Errors {
  double valid_fraction = 0, median_abs = 0;
};

Errors depthErrors(const DepthImage& out, const cv::Mat& truth) {
  std::vector<double> e;
  for (int v = 0; v < truth.rows; ++v)
    for (int u = 0; u < truth.cols; ++u) {
      const float z = out.depth.at<float>(v, u);
      if (std::isfinite(z)) e.push_back(std::abs(z - truth.at<float>(v, u)));
    }
  Errors r;
  r.valid_fraction = static_cast<double>(e.size()) / truth.total();
  if (e.empty()) return r;
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  r.median_abs = e[e.size() / 2];
  return r;
}

TEST(DisparitySearch, CoversTheDepthRange) {
  // f b = 15 px m: 0.5 m -> 30 px, 0.15 m -> 100 px.
  const DisparitySearch s = disparitySearch(0.15, 0.5, 250.0, 0.06);
  EXPECT_EQ(s.min_disparity, 30);
  EXPECT_EQ(s.num_disparities % 16, 0);
  EXPECT_GE(s.min_disparity + s.num_disparities - 1, 100);
  EXPECT_LT(s.num_disparities, 71 + 16);
}

TEST(DenseDepthSettings, RejectsInconsistentValues) {
  DenseDepthSettings s;
  EXPECT_EQ(s.validate(), "");
  s.max_depth = 0.1;
  EXPECT_NE(s.validate(), "");
  s = DenseDepthSettings();
  s.block_size = 4;
  EXPECT_NE(s.validate(), "");
  s = DenseDepthSettings();
  s.lr_tolerance = 0;
  EXPECT_NE(s.validate().find("lr_tolerance"), std::string::npos);
  EXPECT_THROW(DenseDepth{s}, std::invalid_argument);
}

TEST(DenseDepth, SlantedPlaneToSubMillimetre) {
  const cv::Size size(320, 240);
  const RectifiedGeometry g = geometry(size);
  // A plane tilted about the vertical axis: 0.22 m at the left edge to
  // 0.30 m at the right edge; disparity = f b / z.
  cv::Mat z(size, CV_32F), d(size, CV_32F);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      z.at<float>(v, u) = static_cast<float>(0.22 + 0.08 * u / (size.width - 1.0));
      d.at<float>(v, u) = static_cast<float>(g.fx * g.baseline / z.at<float>(v, u));
    }
  const cv::Mat left = speckle(size, 3);
  const cv::Mat right = shiftedRight(left, d);
  DenseDepth matcher{DenseDepthSettings()};
  DepthImage out;
  ASSERT_EQ(matcher.compute(left, right, g, &out), "");
  ASSERT_EQ(out.depth.type(), CV_32FC1);
  ASSERT_EQ(out.confidence.size(), size);
  // Left of u = d the right camera does not see the plane; beyond u = 80
  // every pixel has its match in the right image.
  const cv::Rect seen(80, 0, size.width - 80, size.height);
  const Errors e = depthErrors(DepthImage{out.depth(seen), out.confidence(seen)}, z(seen));
  EXPECT_GT(e.valid_fraction, 0.95);  // the left border is searched too (padding)
  EXPECT_LT(e.median_abs, 0.0005);   // 0.5 mm: about 0.1 px at 0.26 m
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      const float c = out.confidence.at<float>(v, u);
      ASSERT_GE(c, 0.f);
      ASSERT_LE(c, 1.f);
      ASSERT_EQ(std::isfinite(out.depth.at<float>(v, u)), c > 0.f);
    }
}

TEST(DenseDepth, DisparityStepStaysOnItsRow) {
  // Rows above 120 at 0.22 m, from 120 on at 0.28 m: the depth image must
  // change between rows 119 and 120 (the matcher's rows are the image's).
  const cv::Size size(320, 240);
  const RectifiedGeometry g = geometry(size);
  const int step = 120;
  cv::Mat z(size, CV_32F), d(size, CV_32F);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) {
      z.at<float>(v, u) = v < step ? 0.22f : 0.28f;
      d.at<float>(v, u) = static_cast<float>(g.fx * g.baseline / z.at<float>(v, u));
    }
  for (int seed : {4, 5, 6}) {
    const cv::Mat left = speckle(size, seed);
    DenseDepth matcher{DenseDepthSettings()};
    DepthImage out;
    ASSERT_EQ(matcher.compute(left, shiftedRight(left, d), g, &out), "");
    // Per column beyond the unseen left border, the first row nearer the far depth.
    std::vector<int> first_far;
    for (int u = 100; u < size.width; ++u)
      for (int v = step - 10; v < step + 10; ++v)
        if (std::isfinite(out.depth.at<float>(v, u)) && out.depth.at<float>(v, u) > 0.25f) {
          first_far.push_back(v);
          break;
        }
    ASSERT_GT(first_far.size(), 150u);
    std::nth_element(first_far.begin(), first_far.begin() + first_far.size() / 2, first_far.end());
    EXPECT_EQ(first_far[first_far.size() / 2], step) << "seed " << seed;
  }
}

TEST(DenseDepth, FlatRegionsAndOutOfRangeAreInvalid) {
  const cv::Size size(320, 240);
  const RectifiedGeometry g = geometry(size);
  cv::Mat left = speckle(size, 5);
  left(cv::Rect(120, 80, 80, 80)).setTo(128);  // no texture at all
  // Everything at 0.25 m except a band at 0.1 m (nearer than min_depth).
  cv::Mat d(size, CV_32F, cv::Scalar(g.fx * g.baseline / 0.25));
  const cv::Mat right = shiftedRight(left, d);
  DenseDepth matcher{DenseDepthSettings()};
  DepthImage out;
  ASSERT_EQ(matcher.compute(left, right, g, &out), "");
  int flat_valid = 0;
  for (int v = 90; v < 150; ++v)
    for (int u = 130; u < 190; ++u) flat_valid += std::isfinite(out.depth.at<float>(v, u)) ? 1 : 0;
  EXPECT_EQ(flat_valid, 0);
  // Swapped images: every disparity negative, nothing in the depth range;
  // chance matches that pass both checks remain (7 % on this texture).
  DepthImage swapped;
  ASSERT_EQ(matcher.compute(right, left, g, &swapped), "");
  EXPECT_LT(cv::countNonZero(swapped.confidence > 0), static_cast<int>(0.1 * size.area()));
}

TEST(DenseDepth, OccludedPixelsAreInvalid) {
  // A box at disparity 70 px in front of a background at 40 px: the 30 px
  // of background left of the box are hidden from the right camera. Both
  // planes are fronto-parallel, textured in left-image coordinates.
  const cv::Size size(320, 240);
  const RectifiedGeometry g = geometry(size);
  const cv::Mat back = speckle(size, 7), front = speckle(size, 8);
  const cv::Rect box(140, 60, 80, 120);
  const int d_back = 40, d_front = 70;
  cv::Mat left = back.clone();
  front(box).copyTo(left(box));
  cv::Mat right(size, CV_8UC1);
  for (int v = 0; v < size.height; ++v)
    for (int x = 0; x < size.width; ++x) {
      const int uf = x + d_front, ub = std::min(x + d_back, size.width - 1);
      right.at<uchar>(v, x) = box.contains(cv::Point(uf, v)) ? front.at<uchar>(v, uf) : back.at<uchar>(v, ub);
    }
  DepthImage out;
  ASSERT_EQ(DenseDepth(DenseDepthSettings()).compute(left, right, g, &out), "");
  const cv::Rect occluded(box.x - (d_front - d_back) + 3, box.y + 10, d_front - d_back - 6, box.height - 20);
  EXPECT_LT(cv::countNonZero(out.confidence(occluded) > 0), 0.1 * occluded.area());
  // Seen by both cameras: kept.
  const cv::Rect inside(box.x + 10, box.y + 10, box.width - 20, box.height - 20);
  EXPECT_GT(cv::countNonZero(out.confidence(inside) > 0) / static_cast<double>(inside.area()), 0.9);
}

TEST(DenseDepth, LeftRightCheckRemovesMismatches) {
  // Uncorrelated images: SGBM's smoothness still makes a disparity field of
  // them; matched the other way round it is a different one.
  const cv::Size size(320, 240);
  const RectifiedGeometry g = geometry(size);
  const cv::Mat left = speckle(size, 7), right = speckle(size, 8);
  DenseDepthSettings s;
  s.uniqueness_ratio = 0;
  s.speckle_window = 0;
  DepthImage with, without;
  ASSERT_EQ(DenseDepth(s).compute(left, right, g, &with), "");
  s.left_right_check = false;
  ASSERT_EQ(DenseDepth(s).compute(left, right, g, &without), "");
  const int n_with = cv::countNonZero(with.confidence > 0), n_without = cv::countNonZero(without.confidence > 0);
  EXPECT_GT(n_without, 0.5 * size.area());
  EXPECT_LT(n_with, 0.5 * n_without);
}

TEST(DenseDepth, RejectsMismatchedInput) {
  DenseDepth matcher{DenseDepthSettings()};
  DepthImage out;
  const cv::Mat a(240, 320, CV_8UC1, cv::Scalar(0)), b(240, 300, CV_8UC1, cv::Scalar(0));
  EXPECT_NE(matcher.compute(a, b, geometry(a.size()), &out), "");
  EXPECT_NE(matcher.compute(a, a, geometry(b.size()), &out), "");
  const cv::Mat c(240, 320, CV_16UC1, cv::Scalar(0));
  EXPECT_NE(matcher.compute(c, c, geometry(c.size()), &out), "");
  // A baseline of kilometres (a corrupted P): disparities far wider than the image.
  RectifiedGeometry huge = geometry(a.size());
  huge.baseline = 1e300;
  EXPECT_NE(matcher.compute(a, a, huge, &out).find("wider than"), std::string::npos);
}

CameraInfoData info(double fx, double cx, double cy, double tx, std::vector<double> dist) {
  CameraInfoData c;
  c.width = 640;
  c.height = 480;
  c.D = std::move(dist);
  c.K = {fx, 0, cx, 0, fx, cy, 0, 0, 1};
  c.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  c.P = {fx, 0, cx, tx, 0, fx, cy, 0, 0, 0, 1, 0};
  return c;
}

TEST(StereoRectifier, ChecksCalibration) {
  const CameraInfoData l = info(500, 320, 240, 0, {-0.05, 0.01, 0, 0, 0});
  const CameraInfoData r = info(500, 320, 240, -30, {-0.05, 0.01, 0, 0, 0});
  EXPECT_EQ(StereoRectifier::check(l, r), "");
  EXPECT_NE(StereoRectifier::check(l, l), "");  // no baseline
  CameraInfoData bad = r;
  bad.distortion_model = "equidistant";
  EXPECT_NE(StereoRectifier::check(l, bad), "");
  bad = r;
  bad.D = {0.1, 0.2, 0.3};
  EXPECT_NE(StereoRectifier::check(l, bad), "");
  bad = r;
  bad.width = 320;
  EXPECT_NE(StereoRectifier::check(l, bad), "");
  EXPECT_THROW(StereoRectifier(l, l, 0.5), std::invalid_argument);
}

// A fronto-parallel plane at 0.25 m seen through distorting lenses whose
// left and right intrinsics differ (the simulator's rig): the rectified pair
// on the left projection gives the plane's depth at half resolution.
TEST(StereoRectifier, DistortedPairGivesThePlaneDepth) {
  const CameraInfoData l = info(502.3, 321.4, 238.7, 0, {-0.05, 0.01, 2e-4, -1.5e-4, 0});
  CameraInfoData r = info(501.6, 318.9, 240.2, -501.6 * 0.06, {-0.048, 0.009, -1e-4, 1e-4, 0});
  const double z = 0.25;
  const cv::Mat plane = speckle(cv::Size(1400, 900), 11);  // the plane's texture, 0.2 mm per texel
  const double texel = 0.0002;
  auto render = [&](const CameraInfoData& c, double cam_x) {
    // Every raw pixel: undistort to a ray, intersect the plane z = 0.25 m.
    std::vector<cv::Point2f> px, und;
    for (int v = 0; v < c.height; ++v)
      for (int u = 0; u < c.width; ++u) px.emplace_back(static_cast<float>(u), static_cast<float>(v));
    const cv::Mat k(3, 3, CV_64F, const_cast<double*>(c.K.data()));
    cv::undistortPoints(px, und, k, cv::Mat(c.D, true));
    cv::Mat mx(c.height, c.width, CV_32F), my(c.height, c.width, CV_32F);
    for (int i = 0; i < static_cast<int>(und.size()); ++i) {
      const double x = cam_x + und[i].x * z, y = und[i].y * z;
      mx.at<float>(i / c.width, i % c.width) = static_cast<float>(x / texel + plane.cols / 2.0);
      my.at<float>(i / c.width, i % c.width) = static_cast<float>(y / texel + plane.rows / 2.0);
    }
    cv::Mat img;
    cv::remap(plane, img, mx, my, cv::INTER_LINEAR, cv::BORDER_REFLECT);
    return img;
  };
  const cv::Mat left_raw = render(l, 0.0), right_raw = render(r, 0.06);
  const StereoRectifier rect(l, r, 0.5);
  EXPECT_TRUE(rect.builtFrom(l, r, 0.5));
  EXPECT_FALSE(rect.builtFrom(l, r, 1.0));
  EXPECT_NEAR(rect.geometry().baseline, 0.06, 1e-12);
  EXPECT_EQ(rect.geometry().width, 320);
  cv::Mat left, right;
  rect.rectify(left_raw, right_raw, &left, &right);
  ASSERT_EQ(left.size(), cv::Size(320, 240));
  DepthImage out;
  ASSERT_EQ(DenseDepth(DenseDepthSettings()).compute(left, right, rect.geometry(), &out), "");
  const cv::Mat truth(left.size(), CV_32F, cv::Scalar(z));
  const Errors e = depthErrors(out, truth);
  EXPECT_GT(e.valid_fraction, 0.8);
  EXPECT_LT(e.median_abs, 0.001);
}

}  // namespace
}  // namespace hapi_surface
