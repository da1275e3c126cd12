// Own ORB core: determinism (the GPU identity test relies on it), stride
// independence, output layout and the FeatureSet conversion.
#include "hapi_frontend/orb_core.hpp"
#include "hapi_frontend/orb_extractor.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <random>

using namespace hapi_frontend;

namespace {
cv::Mat texturedImage(int w, int h, uint32_t seed) {
  cv::Mat img(h, w, CV_8UC1, cv::Scalar(90));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> X(0, w - 1), Y(0, h - 1), S(3, 25), G(0, 255);
  for (int i = 0; i < 400; ++i) {
    const cv::Point c(X(rng), Y(rng));
    if (i % 2) cv::circle(img, c, S(rng), cv::Scalar(G(rng)), -1);
    else cv::rectangle(img, c, c + cv::Point(S(rng), S(rng)), cv::Scalar(G(rng)), -1);
  }
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}
}  // namespace

TEST(OrbCore, DeterministicAndStrideIndependent) {
  const cv::Mat img = texturedImage(640, 480, 3);
  OrbParams p;
  p.n_features = 500;
  OrbCpuCore a(p), b(p);
  const ImageView8 v{img.data, img.cols, img.rows, static_cast<int>(img.step[0])};
  const OrbResult r1 = a.extract(v), r2 = a.extract(v), r3 = b.extract(v);
  ASSERT_GT(r1.keypoints.size(), 300u);
  ASSERT_LE(r1.keypoints.size(), 500u);
  ASSERT_EQ(r1.descriptors.size(), r1.keypoints.size() * kOrbDescBytes);
  EXPECT_EQ(r1.descriptors, r2.descriptors);
  EXPECT_EQ(r1.descriptors, r3.descriptors);
  // Same pixels inside a wider buffer (stride != width).
  cv::Mat big(480, 700, CV_8UC1, cv::Scalar(7));
  img.copyTo(big(cv::Rect(0, 0, 640, 480)));
  const cv::Mat roi = big(cv::Rect(0, 0, 640, 480));
  const OrbResult r4 = b.extract({roi.data, 640, 480, static_cast<int>(roi.step[0])});
  ASSERT_EQ(r4.keypoints.size(), r1.keypoints.size());
  EXPECT_EQ(r4.descriptors, r1.descriptors);
  for (size_t i = 0; i < r1.keypoints.size(); ++i) {
    const OrbKeypoint& k = r1.keypoints[i];
    EXPECT_EQ(k.lx, r4.keypoints[i].lx);
    EXPECT_EQ(k.ly, r4.keypoints[i].ly);
    EXPECT_EQ(k.angle_bin, r4.keypoints[i].angle_bin);
    EXPECT_GE(k.x, 0.f);
    EXPECT_LT(k.x, 640.f);
    EXPECT_GE(k.y, 0.f);
    EXPECT_LT(k.y, 480.f);
    EXPECT_GT(k.score, p.fast_threshold);
  }
}

TEST(OrbCore, DescriptorsAreDiscriminative) {
  // A shifted copy of the image gives the same keypoints shifted, with nearly
  // identical descriptors; different keypoints differ by ~half the bits.
  const cv::Mat img = texturedImage(640, 480, 4);
  cv::Mat shifted(img.size(), img.type(), cv::Scalar(90));
  img(cv::Rect(0, 0, 630, 480)).copyTo(shifted(cv::Rect(10, 0, 630, 480)));
  OrbExtractor ex(OrbParams(), false);
  EXPECT_FALSE(ex.usingGpu());
  EXPECT_EQ(ex.name(), "orb_cpu");
  const FeatureSet a = ex.extract(img), b = ex.extract(shifted);
  ASSERT_EQ(a.descriptors.cols, 32);
  int same = 0, total = 0;
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    if (a.keypoints[i].octave != 0 || a.keypoints[i].x > 600) continue;
    for (size_t j = 0; j < b.keypoints.size(); ++j)
      if (b.keypoints[j].octave == 0 && b.keypoints[j].x == a.keypoints[i].x + 10 && b.keypoints[j].y == a.keypoints[i].y) {
        ++total;
        same += cv::norm(a.descriptors.row(i), b.descriptors.row(j), cv::NORM_HAMMING) == 0;
      }
  }
  EXPECT_GT(total, 50);
  EXPECT_GT(same, 0.95 * total);
  EXPECT_GT(cv::norm(a.descriptors.row(0), a.descriptors.row(1), cv::NORM_HAMMING), 40);
}
