// The "compressed" image_transport subscriber's decoding (compressed_subscriber.hpp).
#include "compressed_subscriber.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <cstring>

using hapi_frontend::decodeCompressed;

namespace {

sensor_msgs::CompressedImage encode(const cv::Mat& img, const std::string& ext, const std::string& format) {
  sensor_msgs::CompressedImage m;
  m.header.stamp = ros::Time(12, 345);
  m.header.frame_id = "cam";
  m.format = format;
  std::vector<uint8_t> buf;
  EXPECT_TRUE(cv::imencode(ext, img, buf));
  m.data = buf;
  return m;
}

cv::Mat pattern(int type) {
  cv::Mat img(48, 64, type);
  cv::randu(img, cv::Scalar::all(0), cv::Scalar::all(type == CV_16UC1 ? 4096 : 255));
  return img;
}

bool sameBytes(const cv::Mat& a, const sensor_msgs::Image& b) {
  if (a.rows != static_cast<int>(b.height) || a.cols != static_cast<int>(b.width)) return false;
  const std::size_t row = a.cols * a.elemSize();
  for (int r = 0; r < a.rows; ++r)
    if (std::memcmp(a.ptr(r), &b.data[r * b.step], row) != 0) return false;
  return true;
}

}  // namespace

TEST(CompressedSubscriber, PngMono8AndMono16AreLossless) {
  for (int type : {CV_8UC1, CV_16UC1}) {
    const cv::Mat img = pattern(type);
    sensor_msgs::Image out;
    std::string err;
    ASSERT_TRUE(decodeCompressed(encode(img, ".png", "mono; png compressed"), &out, &err)) << err;
    EXPECT_EQ(out.encoding, type == CV_8UC1 ? "mono8" : "mono16");
    EXPECT_EQ(out.header.stamp, ros::Time(12, 345));
    EXPECT_EQ(out.header.frame_id, "cam");
    EXPECT_TRUE(sameBytes(img, out));
  }
}

TEST(CompressedSubscriber, ColourOrderFollowsTheNamedSourceEncoding) {
  const cv::Mat bgr = pattern(CV_8UC3);
  sensor_msgs::Image out;
  std::string err;
  // Upstream writes "<source encoding>; <codec> compressed <data encoding>".
  ASSERT_TRUE(decodeCompressed(encode(bgr, ".png", "bgr8; png compressed bgr8"), &out, &err)) << err;
  EXPECT_EQ(out.encoding, "bgr8");
  EXPECT_TRUE(sameBytes(bgr, out));
  ASSERT_TRUE(decodeCompressed(encode(bgr, ".png", "rgb8; png compressed bgr8"), &out, &err)) << err;
  EXPECT_EQ(out.encoding, "rgb8");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  EXPECT_TRUE(sameBytes(rgb, out));
  // JPEG is lossy: same size and encoding, data close.
  ASSERT_TRUE(decodeCompressed(encode(bgr, ".jpg", "jpeg"), &out, &err)) << err;
  EXPECT_EQ(out.encoding, "bgr8");
  EXPECT_EQ(out.width, 64u);
  EXPECT_EQ(out.height, 48u);
}

TEST(CompressedSubscriber, GarbageGivesAZeroSizeImageWithTheHeader) {
  sensor_msgs::CompressedImage m;
  m.header.stamp = ros::Time(3, 0);
  m.format = "jpeg";
  m.data = {1, 2, 3, 4, 5};
  sensor_msgs::Image out;
  std::string err;
  EXPECT_FALSE(decodeCompressed(m, &out, &err));
  EXPECT_FALSE(err.empty());
  EXPECT_EQ(out.width, 0u);
  EXPECT_EQ(out.height, 0u);
  EXPECT_EQ(out.header.stamp, ros::Time(3, 0));
  m.data.clear();
  err.clear();
  EXPECT_FALSE(decodeCompressed(m, &out, &err));
  EXPECT_FALSE(err.empty());
}

TEST(CompressedSubscriber, AnnouncedSizeOverTheLimitIsRefusedBeforeDecoding) {
  // A valid PNG whose IHDR announces 40000 x 40000 grey (1.6 GB decoded).
  sensor_msgs::CompressedImage m = encode(pattern(CV_8UC1), ".png", "mono8; png compressed");
  for (std::size_t at : {16u, 20u}) {
    m.data[at] = 0;
    m.data[at + 1] = 0;
    m.data[at + 2] = 40000 >> 8;
    m.data[at + 3] = 40000 & 0xFF;
  }
  sensor_msgs::Image out;
  std::string err;
  EXPECT_FALSE(decodeCompressed(m, &out, &err));
  EXPECT_NE(err.find("40000x40000x1"), std::string::npos) << err;
  EXPECT_EQ(out.width, 0u);
  EXPECT_EQ(out.height, 0u);
}
