// ROS message <-> core conversions of the front-end nodelet, without a master:
// every accepted encoding gives the right grey/colour values, bad images and
// calibrations are rejected with the documented reason, and the output
// message carries every field of the core result.
#include "image_input.hpp"
#include "landmarks_message.hpp"

#include <boost/make_shared.hpp>
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <sensor_msgs/image_encodings.h>

namespace hf = hapi_frontend;
namespace enc = sensor_msgs::image_encodings;

namespace {

sensor_msgs::ImagePtr makeImage(const std::string& encoding, int w, int h, int channels, int bytes) {
  auto m = boost::make_shared<sensor_msgs::Image>();
  m->encoding = encoding;
  m->width = w;
  m->height = h;
  m->step = w * channels * bytes;
  m->data.assign(m->step * h, 0);
  return m;
}

sensor_msgs::CameraInfo goodInfo() {
  sensor_msgs::CameraInfo i;
  i.width = 64;
  i.height = 48;
  i.distortion_model = "plumb_bob";
  i.D = {0.1, -0.05, 0.001, 0.0, 0.0};
  i.K = {400, 0, 32, 0, 400, 24, 0, 0, 1};
  i.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  i.P = {400, 0, 32, 0, 0, 400, 24, 0, 0, 0, 1, 0};
  return i;
}

}  // namespace

TEST(ImageInput, Mono8IsSharedWithoutColour) {
  auto m = makeImage(enc::MONO8, 4, 3, 1, 1);
  m->data[5] = 77;
  hf::GreyImage g;
  ASSERT_FALSE(hf::toGrey(m, 16, &g));
  ASSERT_EQ(g.gray.type(), CV_8UC1);
  EXPECT_EQ(g.gray.at<uint8_t>(1, 1), 77);
  EXPECT_TRUE(g.colour.empty());
}

TEST(ImageInput, Rgb8KeepsColourAsBgr) {
  auto m = makeImage(enc::RGB8, 2, 2, 3, 1);
  m->data[0] = 200;  // R of pixel (0,0)
  m->data[1] = 10;   // G
  m->data[2] = 30;   // B
  hf::GreyImage g;
  ASSERT_FALSE(hf::toGrey(m, 16, &g));
  ASSERT_EQ(g.colour.type(), CV_8UC3);
  const cv::Vec3b bgr = g.colour.at<cv::Vec3b>(0, 0);
  EXPECT_EQ(bgr[0], 30);
  EXPECT_EQ(bgr[1], 10);
  EXPECT_EQ(bgr[2], 200);
  // ITU-R BT.601 luma, as cv::cvtColor: 0.299 R + 0.587 G + 0.114 B.
  EXPECT_NEAR(g.gray.at<uint8_t>(0, 0), 0.299 * 200 + 0.587 * 10 + 0.114 * 30, 1.0);
}

TEST(ImageInput, Bgr8GivesSameGreyAsRgb8) {
  auto rgb = makeImage(enc::RGB8, 1, 1, 3, 1);
  auto bgr = makeImage(enc::BGR8, 1, 1, 3, 1);
  rgb->data = {200, 10, 30};
  bgr->data = {30, 10, 200};
  hf::GreyImage a, b;
  ASSERT_FALSE(hf::toGrey(rgb, 16, &a));
  ASSERT_FALSE(hf::toGrey(bgr, 16, &b));
  EXPECT_EQ(a.gray.at<uint8_t>(0, 0), b.gray.at<uint8_t>(0, 0));
  EXPECT_EQ(a.colour.at<cv::Vec3b>(0, 0), b.colour.at<cv::Vec3b>(0, 0));
}

TEST(ImageInput, Mono16ScalesBySignificantBits) {
  auto m = makeImage(enc::MONO16, 2, 1, 1, 2);
  m->is_bigendian = false;
  const uint16_t v0 = 65535, v1 = 4095;
  std::memcpy(&m->data[0], &v0, 2);
  std::memcpy(&m->data[2], &v1, 2);
  hf::GreyImage g16, g12;
  ASSERT_FALSE(hf::toGrey(m, 16, &g16));
  EXPECT_EQ(g16.gray.at<uint8_t>(0, 0), 255);
  EXPECT_EQ(g16.gray.at<uint8_t>(0, 1), 16);  // 4095 * 255 / 65535 = 15.9
  ASSERT_FALSE(hf::toGrey(m, 12, &g12));
  EXPECT_EQ(g12.gray.at<uint8_t>(0, 0), 255);  // saturated
  EXPECT_EQ(g12.gray.at<uint8_t>(0, 1), 255);
}

TEST(ImageInput, RejectsUnsupportedEncodingsAndTruncatedBuffers) {
  hf::GreyImage g;
  for (const char* e : {"bgra8", "32FC1", "bayer_rggb8", "16UC1", ""}) {
    auto m = makeImage(e, 4, 4, 1, 1);
    EXPECT_EQ(hf::toGrey(m, 16, &g).reason, "unsupported_encoding") << e;
  }
  auto shortbuf = makeImage(enc::BGR8, 8, 8, 3, 1);
  shortbuf->data.resize(10);
  EXPECT_EQ(hf::toGrey(shortbuf, 16, &g).reason, "malformed_image");
  auto badstep = makeImage(enc::MONO8, 8, 8, 1, 1);
  badstep->step = 4;
  EXPECT_EQ(hf::toGrey(badstep, 16, &g).reason, "malformed_image");
  auto empty = makeImage(enc::MONO8, 0, 0, 1, 1);
  EXPECT_EQ(hf::toGrey(empty, 16, &g).reason, "malformed_image");
  EXPECT_EQ(hf::toGrey(sensor_msgs::ImageConstPtr(), 16, &g).reason, "malformed_image");
}

TEST(CalibInput, CopiesPlumbBobAndRational) {
  hf::CameraCalib c;
  sensor_msgs::CameraInfo i = goodInfo();
  ASSERT_FALSE(hf::toCalib(i, &c));
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.K[0], 400);
  EXPECT_EQ(c.K[2], 32);
  EXPECT_EQ(c.P[6], 24);
  EXPECT_EQ(c.D.size(), 5u);
  i.distortion_model = "rational_polynomial";
  i.D = {0.1, -0.05, 0.001, 0.0, 0.0, 0.01, 0.0, 0.0};
  ASSERT_FALSE(hf::toCalib(i, &c));
  EXPECT_EQ(c.distortion_model, "rational_polynomial");
  EXPECT_EQ(c.D.size(), 8u);
}

TEST(CalibInput, RejectsZeroKAndUnsupportedSetups) {
  hf::CameraCalib c;
  sensor_msgs::CameraInfo zero = goodInfo();
  zero.K.fill(0.0);
  EXPECT_EQ(hf::toCalib(zero, &c).reason, "invalid_calibration");
  sensor_msgs::CameraInfo empty;  // what an uncalibrated driver publishes
  EXPECT_EQ(hf::toCalib(empty, &c).reason, "invalid_calibration");
  sensor_msgs::CameraInfo nan = goodInfo();
  nan.K[0] = std::nan("");
  EXPECT_EQ(hf::toCalib(nan, &c).reason, "invalid_calibration");
  sensor_msgs::CameraInfo model = goodInfo();
  model.distortion_model = "equidistant";
  model.D = {0.1, 0.0, 0.0, 0.0};
  EXPECT_EQ(hf::toCalib(model, &c).reason, "invalid_calibration");
  sensor_msgs::CameraInfo nd = goodInfo();
  nd.D = {0.1, 0.2};
  EXPECT_EQ(hf::toCalib(nd, &c).reason, "invalid_calibration");
  sensor_msgs::CameraInfo bin = goodInfo();
  bin.binning_x = 2;
  EXPECT_EQ(hf::toCalib(bin, &c).reason, "invalid_calibration");
  sensor_msgs::CameraInfo roi = goodInfo();
  roi.roi.width = 10;
  roi.roi.height = 10;
  EXPECT_EQ(hf::toCalib(roi, &c).reason, "invalid_calibration");
}

TEST(LandmarksMessage, FillsEveryField) {
  hf::StereoFrameResult res;
  res.descriptor_type = hf::DescriptorType::ORB;
  res.descriptors = cv::Mat(2, 32, CV_8UC1);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 32; ++c) res.descriptors.at<uint8_t>(r, c) = static_cast<uint8_t>(r * 100 + c);
  res.landmarks.resize(2);
  for (int i = 0; i < 2; ++i) {
    auto& l = res.landmarks[i];
    l.uv_left = {10.0 + i, 20.0};
    l.uv_right = {5.0 + i, 20.5};
    l.position = {0.1 * i, -0.2, 2.0 + i};
    l.covariance << 1e-4, 1e-6, 2e-6, 1e-6, 2e-4, 3e-6, 2e-6, 3e-6, 5e-3;
    l.response = 50.f - i;
    l.rgb = {{10, 20, static_cast<uint8_t>(30 + i)}};
  }
  std_msgs::Header h;
  h.stamp = ros::Time(12, 345);
  h.frame_id = "stereo_left_optical_frame";

  hapi_msgs::StereoLandmarks msg;
  ASSERT_EQ(hf::fillLandmarksMsg(res, h, &msg), "");
  EXPECT_EQ(msg.header.stamp, h.stamp);
  EXPECT_EQ(msg.header.frame_id, "stereo_left_optical_frame");
  EXPECT_EQ(msg.descriptor_type, hapi_msgs::StereoLandmarks::DESCRIPTOR_ORB);
  EXPECT_EQ(msg.descriptor_length, 32u);
  ASSERT_EQ(msg.descriptors.size(), 64u);
  EXPECT_EQ(msg.descriptors[32 + 5], 105);  // row 1, byte 5
  ASSERT_EQ(msg.landmarks.size(), 2u);
  const auto& l1 = msg.landmarks[1];
  EXPECT_EQ(l1.id, 1u);
  EXPECT_EQ(l1.position.x, 0.1);
  EXPECT_EQ(l1.position.y, -0.2);
  EXPECT_EQ(l1.position.z, 3.0);
  EXPECT_EQ(l1.position_covariance[1], 1e-6);  // row-major (0,1)
  EXPECT_EQ(l1.position_covariance[5], 3e-6);  // (1,2)
  EXPECT_EQ(l1.position_covariance[8], 5e-3);
  EXPECT_FLOAT_EQ(l1.response, 49.f);
  EXPECT_EQ(l1.b, 31);
}

TEST(LandmarksMessage, RejectsInconsistentResults) {
  hf::StereoFrameResult res;
  res.landmarks.resize(3);
  res.descriptors = cv::Mat(2, 32, CV_8UC1, cv::Scalar(0));
  hapi_msgs::StereoLandmarks msg;
  EXPECT_NE(hf::fillLandmarksMsg(res, std_msgs::Header(), &msg), "");
  res.descriptors = cv::Mat(3, 32, CV_8UC1, cv::Scalar(0));
  res.landmarks[2].position.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(hf::fillLandmarksMsg(res, std_msgs::Header(), &msg), "");
}
