// convertToGrey: every accepted encoding, byte order, the robust float
// normalisation, and the rejections.
#include "hapi_frontend/grey_convert.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

namespace hapi_frontend {
namespace {

RawImageView view(const std::string& enc, int w, int h, int bpp, const std::vector<std::uint8_t>& data) {
  RawImageView v;
  v.encoding = enc;
  v.width = w;
  v.height = h;
  v.step = w * bpp;
  v.data = data.data();
  v.size = data.size();
  return v;
}

template <typename T>
std::vector<std::uint8_t> bytes(const std::vector<T>& values) {
  std::vector<std::uint8_t> b(values.size() * sizeof(T));
  std::memcpy(b.data(), values.data(), b.size());
  return b;
}

TEST(GreyConvert, EveryEncodingGivesTheExpectedGrey) {
  cv::Mat g;
  // mono8: wrapped as it is.
  const std::vector<std::uint8_t> mono8 = {0, 10, 200, 255, 7, 9};
  ASSERT_FALSE(convertToGrey(view("mono8", 3, 2, 1, mono8), 16, &g));
  EXPECT_EQ(g.type(), CV_8UC1);
  EXPECT_EQ(g.at<std::uint8_t>(1, 2), 9);
  EXPECT_EQ(g.data, mono8.data());
  // mono16 with 12 significant bits: 4095 -> 255, 2048 -> 128.
  const auto mono16 = bytes(std::vector<std::uint16_t>{0, 2048, 4095, 65535});
  ASSERT_FALSE(convertToGrey(view("mono16", 2, 2, 2, mono16), 12, &g));
  EXPECT_EQ(g.at<std::uint8_t>(0, 0), 0);
  EXPECT_EQ(g.at<std::uint8_t>(0, 1), 128);
  EXPECT_EQ(g.at<std::uint8_t>(1, 0), 255);
  EXPECT_EQ(g.at<std::uint8_t>(1, 1), 255);  // saturated
  // Big-endian mono16.
  const std::vector<std::uint8_t> be = {0x08, 0x00, 0x0f, 0xff};
  RawImageView bev = view("mono16", 2, 1, 2, be);
  bev.bigendian = true;
  ASSERT_FALSE(convertToGrey(bev, 12, &g));
  EXPECT_EQ(g.at<std::uint8_t>(0, 0), 128);
  EXPECT_EQ(g.at<std::uint8_t>(0, 1), 255);
  // Colour: pure red, green, blue pixels give the BT.601 luma 76, 150, 29.
  const std::vector<std::uint8_t> bgr = {0, 0, 255, 0, 255, 0, 255, 0, 0};
  const std::vector<std::uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255};
  const std::vector<std::uint8_t> bgra = {0, 0, 255, 9, 0, 255, 0, 9, 255, 0, 0, 9};
  for (const auto& c : {std::make_pair("bgr8", &bgr), std::make_pair("rgb8", &rgb), std::make_pair("bgra8", &bgra)}) {
    const int bpp = std::string(c.first) == "bgra8" ? 4 : 3;
    ASSERT_FALSE(convertToGrey(view(c.first, 3, 1, bpp, *c.second), 16, &g)) << c.first;
    EXPECT_EQ(g.at<std::uint8_t>(0, 0), 76) << c.first;
    EXPECT_EQ(g.at<std::uint8_t>(0, 1), 150) << c.first;
    EXPECT_EQ(g.at<std::uint8_t>(0, 2), 29) << c.first;
  }
}

TEST(GreyConvert, FloatMapsAreNormalisedRobustly) {
  // A ramp 0..999 with one huge outlier and a NaN: the 1st/99th percentiles
  // (about 10 and 989) span 0..255, the outlier saturates, NaN is 0.
  std::vector<float> f(1000);
  for (int i = 0; i < 1000; ++i) f[i] = static_cast<float>(i);
  f[500] = 1e30f;
  f[501] = std::numeric_limits<float>::quiet_NaN();
  const auto b = bytes(f);
  cv::Mat g;
  ASSERT_FALSE(convertToGrey(view("32FC1", 100, 10, 4, b), 16, &g));
  EXPECT_EQ(g.at<std::uint8_t>(0, 5), 0);      // below the 1st percentile
  EXPECT_EQ(g.at<std::uint8_t>(9, 99), 255);   // above the 99th
  EXPECT_EQ(g.at<std::uint8_t>(5, 0), 255);    // the outlier
  EXPECT_EQ(g.at<std::uint8_t>(5, 1), 0);      // NaN
  EXPECT_NEAR(g.at<std::uint8_t>(4, 99), 127, 3);  // value 499: the middle
  // A flat or all-NaN map: no texture, no division by zero.
  const auto flat = bytes(std::vector<float>(16, 3.5f));
  ASSERT_FALSE(convertToGrey(view("32FC1", 4, 4, 4, flat), 16, &g));
  EXPECT_EQ(g.at<std::uint8_t>(2, 2), 128);
  const auto nan = bytes(std::vector<float>(16, std::numeric_limits<float>::quiet_NaN()));
  ASSERT_FALSE(convertToGrey(view("32FC1", 4, 4, 4, nan), 16, &g));
  EXPECT_EQ(cv::countNonZero(g), 0);
}

TEST(GreyConvert, BadBuffersAndEncodingsAreRejected) {
  cv::Mat g;
  const std::vector<std::uint8_t> d(12, 1);
  EXPECT_EQ(convertToGrey(view("yuv422", 2, 2, 2, d), 16, &g).reason, "unsupported_encoding");
  EXPECT_EQ(convertToGrey(view("64FC1", 1, 1, 8, d), 16, &g).reason, "unsupported_encoding");
  EXPECT_EQ(convertToGrey(view("rgb8", 2, 2, 3, std::vector<std::uint8_t>(11, 0)), 16, &g).reason, "malformed_image");
  RawImageView short_step = view("mono16", 3, 2, 2, d);
  short_step.step = 5;  // shorter than a row
  EXPECT_EQ(convertToGrey(short_step, 16, &g).reason, "malformed_image");
  EXPECT_EQ(convertToGrey(view("mono8", 0, 2, 1, d), 16, &g).reason, "malformed_image");
  RawImageView none = view("mono8", 2, 2, 1, d);
  none.data = nullptr;
  EXPECT_EQ(convertToGrey(none, 16, &g).reason, "malformed_image");
  RawImageView huge = view("mono8", 1u << 31, 2, 1, d);
  huge.step = 0xffffffffu;
  EXPECT_EQ(convertToGrey(huge, 16, &g).reason, "malformed_image");
  EXPECT_EQ(convertToGrey(view("mono8", 2, 2, 1, d), 7, &g).reason, "invalid_setting");
}

}  // namespace
}  // namespace hapi_frontend
