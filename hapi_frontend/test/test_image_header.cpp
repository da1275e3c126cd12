// PNG/JPEG header reading and the decode bound (image_header.hpp), on
// streams OpenCV writes and on hand-made hostile headers.
#include "hapi_frontend/image_header.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include <vector>

using hapi_frontend::AnnouncedImage;
using hapi_frontend::checkDecodable;
using hapi_frontend::kMaxDecodedImageBytes;
using hapi_frontend::readImageHeader;

namespace {

std::vector<std::uint8_t> encode(int type, const std::string& ext, const std::vector<int>& options = {}) {
  cv::Mat img(37, 53, type);
  cv::randu(img, cv::Scalar::all(0), cv::Scalar::all(200));
  std::vector<std::uint8_t> buf;
  EXPECT_TRUE(cv::imencode(ext, img, buf, options));
  return buf;
}

AnnouncedImage read(const std::vector<std::uint8_t>& bytes) {
  AnnouncedImage image;
  std::string error;
  EXPECT_TRUE(readImageHeader(bytes.data(), bytes.size(), &image, &error)) << error;
  return image;
}

void put32(std::vector<std::uint8_t>* b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) (*b)[at + k] = static_cast<std::uint8_t>(v >> (24 - 8 * k));
}

}  // namespace

TEST(ImageHeader, ReadsWhatOpenCvWrites) {
  struct Case {
    int type;
    const char* ext;
    std::vector<int> options;
    const char* codec;
    int channels;
    int bytes;
  };
  const std::vector<Case> cases = {
      {CV_8UC1, ".png", {}, "png", 1, 1},
      {CV_16UC1, ".png", {}, "png", 1, 2},
      {CV_8UC3, ".png", {}, "png", 3, 1},
      {CV_8UC4, ".png", {}, "png", 4, 1},
      {CV_8UC1, ".jpg", {}, "jpeg", 1, 1},
      {CV_8UC3, ".jpg", {}, "jpeg", 3, 1},
      {CV_8UC3, ".jpg", {cv::IMWRITE_JPEG_PROGRESSIVE, 1}, "jpeg", 3, 1},
  };
  for (const Case& c : cases) {
    const AnnouncedImage image = read(encode(c.type, c.ext, c.options));
    EXPECT_EQ(image.codec, c.codec) << c.ext;
    EXPECT_EQ(image.width, 53u) << c.ext;
    EXPECT_EQ(image.height, 37u) << c.ext;
    EXPECT_EQ(image.channels, c.channels) << c.ext << " type " << c.type;
    EXPECT_EQ(image.bytes_per_channel, c.bytes) << c.ext;
    EXPECT_EQ(checkDecodable(encode(c.type, c.ext, c.options).data(), encode(c.type, c.ext, c.options).size(),
                             kMaxDecodedImageBytes),
              "");
  }
}

TEST(ImageHeader, JpegBytesBetweenMarkersAreSkippedAsLibjpegDoes) {
  std::vector<std::uint8_t> jpeg = encode(CV_8UC1, ".jpg");
  // Garbage, a stuffed 0xFF 0x00 and fill bytes after the first segment
  // (APP0; libjpeg: "extraneous bytes before marker").
  ASSERT_EQ(jpeg[3], 0xE0);
  const std::size_t after_app0 = 4 + ((jpeg[4] << 8) | jpeg[5]);
  jpeg.insert(jpeg.begin() + after_app0, {0x12, 0x34, 0x00, 0xFF, 0x00, 0xFF, 0xFF});
  const AnnouncedImage image = read(jpeg);
  EXPECT_EQ(image.width, 53u);
  EXPECT_EQ(image.height, 37u);
  const cv::Mat decoded = cv::imdecode(jpeg, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(decoded.cols, 53);
}

TEST(ImageHeader, RefusesAPngBombBeforeDecoding) {
  // A valid 53x37 PNG whose IHDR is rewritten to announce 60000 x 60000
  // RGBA 16-bit (28.8 GB): the size check fails on the header alone.
  std::vector<std::uint8_t> png = encode(CV_8UC4, ".png");
  put32(&png, 16, 60000);
  put32(&png, 20, 60000);
  png[24] = 16;
  const std::string why = checkDecodable(png.data(), png.size(), kMaxDecodedImageBytes);
  EXPECT_NE(why.find("60000x60000x4"), std::string::npos) << why;
  EXPECT_NE(why.find("limit"), std::string::npos) << why;
  // The bound is the caller's: the same header passes a large enough one.
  EXPECT_EQ(checkDecodable(png.data(), png.size(), 60000ull * 60000 * 8), "");
}

TEST(ImageHeader, RefusesAJpegBombBeforeDecoding) {
  std::vector<std::uint8_t> jpeg = encode(CV_8UC3, ".jpg");
  // Find SOF0 and announce 65535 x 65535.
  std::size_t sof = 0;
  for (std::size_t i = 2; i + 1 < jpeg.size(); ++i)
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xC0) {
      sof = i;
      break;
    }
  ASSERT_GT(sof, 0u);
  jpeg[sof + 5] = jpeg[sof + 6] = jpeg[sof + 7] = jpeg[sof + 8] = 0xFF;
  EXPECT_NE(checkDecodable(jpeg.data(), jpeg.size(), kMaxDecodedImageBytes).find("65535x65535x3"), std::string::npos);
}

TEST(ImageHeader, RefusesOtherFormatsTruncatedAndEmptyHeaders) {
  AnnouncedImage image;
  std::string error;
  const std::vector<std::uint8_t> bmp = encode(CV_8UC1, ".bmp");
  EXPECT_FALSE(readImageHeader(bmp.data(), bmp.size(), &image, &error));
  EXPECT_EQ(error, "neither PNG nor JPEG data");

  for (const char* ext : {".png", ".jpg"}) {
    const std::vector<std::uint8_t> full = encode(CV_8UC1, ext);
    // Every prefix that ends before the size is known is refused, none crashes.
    for (std::size_t n = 0; n < 24; ++n) {
      error.clear();
      EXPECT_FALSE(readImageHeader(full.data(), n, &image, &error)) << ext << " prefix " << n;
      EXPECT_FALSE(error.empty());
    }
    std::vector<std::uint8_t> zero = full;
    if (std::string(ext) == ".png") {
      put32(&zero, 16, 0);
    } else {
      for (std::size_t i = 2; i + 1 < zero.size(); ++i)
        if (zero[i] == 0xFF && zero[i + 1] == 0xC0) {
          zero[i + 5] = zero[i + 6] = 0;  // height 0 (a DNL marker would follow)
          break;
        }
    }
    EXPECT_FALSE(readImageHeader(zero.data(), zero.size(), &image, &error)) << ext;
    EXPECT_NE(error.find("announces a"), std::string::npos) << error;
  }
}
