// The block matcher of DenseDepth's GPU path: its CPU reference on a known
// shift, on a flat image, and in DenseDepth (use_gpu without a device). The
// kernel against it: test_dense_depth_cuda.cpp.
#include "hapi_surface/dense_depth.hpp"
#include "hapi_surface/dense_depth_block_match.hpp"
#include "test_dense_depth_images.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hapi_surface {
namespace {

using test_images::speckle;

// The left image shifted by a constant disparity d (px, sub-pixel).
cv::Mat shifted(const cv::Mat& left, double d) {
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, -d, 0, 1, 0);
  cv::Mat right;
  cv::warpAffine(left, right, m, left.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return right;
}

TEST(BlockMatch, CpuReferenceFindsTheDisparity) {
  const cv::Mat left = speckle(cv::Size(160, 120), 4), right = shifted(left, 40.3);
  const BlockMatchParams p{30, 32, 7, 10};
  std::vector<float> d(left.total());
  blockMatchCpu(left.data, right.data, left.cols, left.rows, static_cast<int>(left.step), p, d.data());
  std::vector<double> err;
  for (int y = 5; y < left.rows - 5; ++y)
    for (int x = 50; x < left.cols - 5; ++x) {  // x >= d: seen by both
      const float v = d[static_cast<std::size_t>(y) * left.cols + x];
      if (v >= p.min_disparity) err.push_back(std::abs(v - 40.3));
    }
  ASSERT_GT(err.size(), 0.9 * (left.rows - 10) * (left.cols - 55));
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  EXPECT_LT(err[err.size() / 2], 0.15);  // parabola sub-pixel: a tenth of a pixel
}

TEST(BlockMatch, FlatImageHasNoUniqueMinimum) {
  const cv::Mat flat(60, 80, CV_8UC1, cv::Scalar(90));
  const BlockMatchParams p{4, 16, 5, 10};
  std::vector<float> d(flat.total());
  blockMatchCpu(flat.data, flat.data, flat.cols, flat.rows, static_cast<int>(flat.step), p, d.data());
  for (float v : d) ASSERT_EQ(v, p.min_disparity - 1);
}

TEST(BlockMatch, DenseDepthGpuPathGivesThePlane) {
  // use_gpu without a device runs the same matcher on the CPU.
  const cv::Size size(320, 240);
  RectifiedGeometry g;
  g.fx = g.fy = 250;
  g.cx = 160;
  g.cy = 120;
  g.baseline = 0.06;
  g.width = size.width;
  g.height = size.height;
  const double z = 0.25, d = g.fx * g.baseline / z;  // 60 px
  const cv::Mat left = speckle(size, 9), right = shifted(left, d);
  DenseDepthSettings s;
  s.use_gpu = true;
  DepthImage out;
  ASSERT_EQ(DenseDepth(s).compute(left, right, g, &out), "");
  std::vector<double> err;
  for (int v = 0; v < size.height; ++v)
    for (int u = 80; u < size.width; ++u) {
      const float zz = out.depth.at<float>(v, u);
      if (std::isfinite(zz)) err.push_back(std::abs(zz - z));
    }
  EXPECT_GT(err.size(), 0.9 * size.height * (size.width - 80));
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  EXPECT_LT(err[err.size() / 2], 0.0005);
}

}  // namespace
}  // namespace hapi_surface
