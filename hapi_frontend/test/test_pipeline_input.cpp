// StereoPipeline: parameter validation and bad input -> reason string, never
// an exception or a crash.
#include "hapi_frontend/stereo_pipeline.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace hapi_frontend;

namespace {
CameraCalib calib(double tx) {
  CameraCalib c;
  c.width = 320;
  c.height = 240;
  c.D = {-0.05, 0.01, 0, 0, 0};
  c.K = {250, 0, 160, 0, 250, 120, 0, 0, 1};
  c.P = {250, 0, 160, tx, 0, 250, 120, 0, 0, 0, 1, 0};
  return c;
}
cv::Mat noise(int w, int h, int type) {
  cv::Mat m(h, w, type);
  cv::randu(m, 0, type == CV_16UC1 ? 65535 : 255);
  return m;
}
}  // namespace

TEST(PipelineParams, ValidationRejectsNonsense) {
  PipelineParams p;
  EXPECT_EQ(p.validate(), "");
  p.detector = "sift";
  EXPECT_NE(p.validate(), "");
  EXPECT_THROW(StereoPipeline{p}, std::invalid_argument);
  p = PipelineParams();
  p.downscale = 0.5;
  EXPECT_NE(p.validate(), "");
  p = PipelineParams();
  p.min_depth = 3;
  p.max_depth = 1;
  EXPECT_NE(p.validate(), "");
  p = PipelineParams();
  p.pixel_sigma = 0;
  EXPECT_NE(p.validate(), "");
  p = PipelineParams();
  p.match.ratio = 1.5;
  EXPECT_NE(p.validate(), "");
}

TEST(StereoPipeline, BadCalibrationIsReported) {
  StereoPipeline pipe{PipelineParams()};
  CameraCalib zero;
  EXPECT_NE(pipe.setCalibration(zero, calib(-15)), "");
  EXPECT_FALSE(pipe.hasCalibration());
  EXPECT_NE(pipe.setCalibration(calib(0), calib(0)), "");  // no baseline
  CameraCalib other = calib(-15);
  other.width = 640;
  EXPECT_NE(pipe.setCalibration(calib(0), other), "");
  EXPECT_EQ(pipe.setCalibration(calib(0), calib(-15)), "");
  EXPECT_TRUE(pipe.hasCalibration());
  EXPECT_NEAR(pipe.rig().t_lr.x(), 0.06, 1e-12);
}

TEST(StereoPipeline, BadImagesGiveReasonsNotExceptions) {
  StereoPipeline pipe{PipelineParams()};
  StereoFrameResult out;
  const cv::Mat g = noise(320, 240, CV_8UC1);
  EXPECT_NE(pipe.process(g, g, cv::Mat(), &out), "");  // no calibration yet
  ASSERT_EQ(pipe.setCalibration(calib(0), calib(-15)), "");
  EXPECT_NE(pipe.process(cv::Mat(), g, cv::Mat(), &out), "");
  EXPECT_NE(pipe.process(g, noise(321, 240, CV_8UC1), cv::Mat(), &out), "");
  EXPECT_NE(pipe.process(noise(640, 480, CV_8UC1), noise(640, 480, CV_8UC1), cv::Mat(), &out), "");
  EXPECT_NE(pipe.process(noise(320, 240, CV_32FC1), noise(320, 240, CV_32FC1), cv::Mat(), &out), "");
  EXPECT_NE(pipe.process(g, g, noise(100, 100, CV_8UC3), &out), "");
  EXPECT_NE(pipe.process(g, g, cv::Mat(), nullptr), "");
  EXPECT_TRUE(out.landmarks.empty());
  // Supported encodings run (random noise: few or no landmarks, but no error).
  EXPECT_EQ(pipe.process(g, g, cv::Mat(), &out), "");
  EXPECT_EQ(pipe.process(noise(320, 240, CV_8UC3), noise(320, 240, CV_8UC3), noise(320, 240, CV_8UC3), &out), "");
  EXPECT_EQ(pipe.process(noise(320, 240, CV_16UC1), noise(320, 240, CV_16UC1), cv::Mat(), &out), "");
  EXPECT_EQ(pipe.process(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0)), cv::Mat(240, 320, CV_8UC1, cv::Scalar(0)),
                         cv::Mat(), &out), "");
  EXPECT_EQ(out.n_left, 0);
  EXPECT_TRUE(out.landmarks.empty());
  EXPECT_EQ(out.descriptors.rows, 0);
}

// use_gpu without a usable device (or without CUDA in the build) falls back
// to the CPU path and says so through used_gpu; results are the CPU ones.
TEST(StereoPipeline, GpuRequestFallsBackCleanly) {
  PipelineParams p;
  p.use_gpu = true;
  StereoPipeline gpu(p);
  p.use_gpu = false;
  StereoPipeline cpu(p);
  ASSERT_EQ(gpu.setCalibration(calib(0), calib(-15)), "");
  ASSERT_EQ(cpu.setCalibration(calib(0), calib(-15)), "");
  cv::Mat img(240, 320, CV_8UC1);
  cv::randu(img, 0, 255);
  cv::Mat right = img.clone();
  img(cv::Rect(8, 0, 312, 240)).copyTo(right(cv::Rect(0, 0, 312, 240)));  // 8 px disparity
  StereoFrameResult a, b;
  ASSERT_EQ(gpu.process(img, right, cv::Mat(), &a), "");
  ASSERT_EQ(cpu.process(img, right, cv::Mat(), &b), "");
  ASSERT_EQ(a.landmarks.size(), b.landmarks.size());
  for (size_t i = 0; i < a.landmarks.size(); ++i) EXPECT_EQ(a.landmarks[i].position, b.landmarks[i].position);
  if (!a.used_gpu) SUCCEED() << "no CUDA device: CPU fallback";
}
