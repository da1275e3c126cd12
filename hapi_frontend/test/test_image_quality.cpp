// image_quality.hpp: the epipolar offset's size and sign, the median, and
// the motion blur telling smeared from sharp images whatever the texture's
// contrast and the motion's direction.
#include "hapi_frontend/image_quality.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

namespace hapi_frontend {
namespace {

// F of a rectified pair with equal K: the epipolar line of (x, y) is row y.
Eigen::Matrix3d rectifiedF() {
  Eigen::Matrix3d F;
  F << 0, 0, 0, 0, 0, -1, 0, 1, 0;
  return F;
}

TEST(EpipolarOffset, IsTheVerticalDisparityOfARectifiedPairWhateverTheScaleOfF) {
  const Eigen::Vector2d l(320, 200);
  for (double scale : {1.0, -3.0, 0.01}) {
    const Eigen::Matrix3d F = scale * rectifiedF();
    EXPECT_NEAR(epipolarOffset(F, l, Eigen::Vector2d(300, 201.5)), 1.5, 1e-12) << scale;
    EXPECT_NEAR(epipolarOffset(F, l, Eigen::Vector2d(250, 199.25)), -0.75, 1e-12) << scale;
  }
  EXPECT_TRUE(std::isnan(epipolarOffset(Eigen::Matrix3d::Zero(), l, l)));
}

TEST(Median, OddEvenAndEmpty) {
  EXPECT_DOUBLE_EQ(median({3.0, -1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_TRUE(std::isnan(median({})));
}

// A natural-looking texture: white noise smoothed over ~1.5 px, plus the
// sensor's shot noise, in 8 bit around mid-grey with the given contrast.
cv::Mat texture(double contrast, uint64 seed) {
  cv::Mat noise(480, 640, CV_32F), img;
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
  cv::normalize(noise, noise, 0, 1, cv::NORM_MINMAX);
  noise = 128.0 + contrast * 255.0 * (noise - 0.5);
  cv::Mat sensor(noise.size(), CV_32F);
  rng.fill(sensor, cv::RNG::NORMAL, 0.0, 2.0);
  noise += sensor;
  noise.convertTo(img, CV_8U);
  return img;
}

// Motion smear over `length` px along a horizontal or diagonal line.
cv::Mat smear(const cv::Mat& img, int length, bool diagonal) {
  cv::Mat k = cv::Mat::zeros(diagonal ? length : 1, length, CV_32F), out;
  for (int i = 0; i < length; ++i) k.at<float>(diagonal ? i : 0, i) = 1.0f / length;
  cv::filter2D(img, out, -1, k);
  return out;
}

TEST(MotionBlur, SmearedImagesScoreHigherThanSharpOnesAtAnyContrastAndDirection) {
  for (double contrast : {0.8, 0.25}) {
    const cv::Mat sharp = texture(contrast, 7);
    EXPECT_LT(motionBlur(sharp), 0.1) << contrast;
    EXPECT_LT(motionBlur(smear(sharp, 3, false)), 0.3) << contrast;
    for (bool diagonal : {false, true}) {
      // config/frontend.yaml check_max_motion_blur: 0.4
      EXPECT_GT(motionBlur(smear(sharp, 9, diagonal)), 0.4) << contrast << " " << diagonal;
      const double smeared = motionBlur(smear(sharp, 15, diagonal));
      EXPECT_GT(smeared, 0.6) << contrast << " " << diagonal;
      EXPECT_LE(smeared, 1.0);
    }
  }
  EXPECT_NEAR(motionBlur(smear(texture(0.8, 3), 9, false)), motionBlur(smear(texture(0.25, 3), 9, false)), 0.05);
}

TEST(MotionBlur, UniformOrWrongTypeIsNotJudged) {
  EXPECT_TRUE(std::isnan(motionBlur(cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)))));
  EXPECT_TRUE(std::isnan(motionBlur(cv::Mat(480, 640, CV_32F, cv::Scalar(0.5)))));
  EXPECT_TRUE(std::isnan(motionBlur(cv::Mat())));
}

}  // namespace
}  // namespace hapi_frontend
