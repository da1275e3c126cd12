// The float conversion of camera buffers (every encoding, byte order, bad
// headers) and the PLY writer/reader (round trip, hostile files).
#include "hapi_surface/float_image.hpp"
#include "hapi_surface/ply_io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace hapi_surface {
namespace {

RawImageView view(const std::string& enc, std::uint32_t w, std::uint32_t h, std::uint32_t step,
                  const std::vector<std::uint8_t>& bytes, bool big = false) {
  RawImageView v;
  v.encoding = enc;
  v.width = w;
  v.height = h;
  v.step = step;
  v.bigendian = big;
  v.data = bytes.data();
  v.size = bytes.size();
  return v;
}

TEST(FloatImage, Mono8WithRowPadding) {
  FloatImage f;
  const std::vector<std::uint8_t> b = {0, 7, 99, 255, 9, 99};  // 2 x 2, step 3
  ASSERT_EQ(toFloatImage(view("mono8", 2, 2, 3, b), &f), SurfaceStatus::kOk);
  EXPECT_EQ(f.data, (std::vector<float>{0, 7, 255, 9}));
}

TEST(FloatImage, Mono8ConfidenceIsAWeightOfAtMostOne) {
  FloatImage f;
  const std::vector<std::uint8_t> b = {0, 51, 255, 0};
  ASSERT_EQ(toConfidenceImage(view("mono8", 2, 2, 2, b), &f), SurfaceStatus::kOk);
  ASSERT_EQ(f.data.size(), 4u);
  EXPECT_FLOAT_EQ(f.data[0], 0.f);
  EXPECT_FLOAT_EQ(f.data[1], 0.2f);
  EXPECT_FLOAT_EQ(f.data[2], 1.f);
  const std::vector<std::uint8_t> x = {0, 0, 0x80, 0x3f};  // 1.0f, little-endian 32FC1
  ASSERT_EQ(toConfidenceImage(view("32FC1", 1, 1, 4, x), &f), SurfaceStatus::kOk);
  EXPECT_EQ(f.data, (std::vector<float>{1}));
}

TEST(FloatImage, Mono16BothByteOrders) {
  FloatImage f;
  const std::vector<std::uint8_t> le = {0x34, 0x12, 0xff, 0xff};
  ASSERT_EQ(toFloatImage(view("mono16", 2, 1, 4, le), &f), SurfaceStatus::kOk);
  EXPECT_EQ(f.data, (std::vector<float>{0x1234, 65535}));
  const std::vector<std::uint8_t> be = {0x12, 0x34, 0x00, 0x01};
  ASSERT_EQ(toFloatImage(view("16UC1", 2, 1, 4, be, true), &f), SurfaceStatus::kOk);
  EXPECT_EQ(f.data, (std::vector<float>{0x1234, 1}));
}

TEST(FloatImage, ColourToLuma) {
  FloatImage f;
  const std::vector<std::uint8_t> rgb = {255, 0, 0, 0, 0, 255};
  ASSERT_EQ(toFloatImage(view("rgb8", 2, 1, 6, rgb), &f), SurfaceStatus::kOk);
  EXPECT_NEAR(f.data[0], 0.299f * 255, 1e-3);
  EXPECT_NEAR(f.data[1], 0.114f * 255, 1e-3);
  ASSERT_EQ(toFloatImage(view("bgr8", 2, 1, 6, rgb), &f), SurfaceStatus::kOk);
  EXPECT_NEAR(f.data[0], 0.114f * 255, 1e-3);
  const std::vector<std::uint8_t> bgra = {0, 255, 0, 17};
  ASSERT_EQ(toFloatImage(view("bgra8", 1, 1, 4, bgra), &f), SurfaceStatus::kOk);
  EXPECT_NEAR(f.data[0], 0.587f * 255, 1e-3);
}

TEST(FloatImage, Float32KeepsValuesAndNaN) {
  const float v[3] = {1.25f, std::numeric_limits<float>::quiet_NaN(), -3.5f};
  std::vector<std::uint8_t> b(12), be(12);
  std::memcpy(b.data(), v, 12);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 4; ++k) be[4 * i + k] = b[4 * i + 3 - k];
  FloatImage f;
  ASSERT_EQ(toFloatImage(view("32FC1", 3, 1, 12, b), &f), SurfaceStatus::kOk);
  EXPECT_EQ(f.data[0], 1.25f);
  EXPECT_TRUE(std::isnan(f.data[1]));
  EXPECT_EQ(f.data[2], -3.5f);
  ASSERT_EQ(toFloatImage(view("32FC1", 3, 1, 12, be, true), &f), SurfaceStatus::kOk);
  EXPECT_EQ(f.data[2], -3.5f);
}

TEST(FloatImage, BadHeadersLeaveTheOutputAlone) {
  FloatImage f;
  f.width = 1;
  f.height = 1;
  f.data = {42.f};
  const std::vector<std::uint8_t> b(64, 1);
  EXPECT_EQ(toFloatImage(view("yuv422", 4, 4, 8, b), &f), SurfaceStatus::kUnknownEncoding);
  EXPECT_EQ(toFloatImage(view("mono16", 4, 4, 7, b), &f), SurfaceStatus::kMalformedImage);  // step < row
  EXPECT_EQ(toFloatImage(view("mono8", 8, 9, 8, b), &f), SurfaceStatus::kMalformedImage);   // 72 > 64 bytes
  EXPECT_EQ(toFloatImage(view("mono8", 0, 4, 8, b), &f), SurfaceStatus::kMalformedImage);
  EXPECT_EQ(toFloatImage(view("mono8", 1, 1u << 20, 1, b), &f), SurfaceStatus::kMalformedImage);
  EXPECT_EQ(f.data, std::vector<float>{42.f});
}

Mesh twoTriangles() {
  Mesh m;
  m.vertices = {{0, 0, 0.25f}, {0.01f, 0, 0.25f}, {0, 0.01f, 0.25f}, {0.01f, 0.01f, 0.26f}};
  m.normals = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}, {0, 0.1f, -0.99f}};
  m.faces = {{0, 1, 2}, {1, 3, 2}};
  m.values = {1.5f, std::numeric_limits<float>::quiet_NaN(), 3.f, 4.f};
  m.value_weights = {1, 0, 2, 3};
  return m;
}

TEST(Ply, RoundTrip) {
  const Mesh m = twoTriangles();
  const std::vector<Rgb8> colours = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}};
  Mesh r;
  std::vector<Rgb8> rc;
  std::string why;
  ASSERT_EQ(parsePly(plyBytes(m, colours), &r, &rc, &why), SurfaceStatus::kOk) << why;
  EXPECT_EQ(r.vertices, m.vertices);
  EXPECT_EQ(r.normals, m.normals);
  EXPECT_EQ(r.faces, m.faces);
  EXPECT_EQ(rc, colours);
  EXPECT_EQ(r.values[0], 1.5f);
  EXPECT_TRUE(std::isnan(r.values[1]));
  EXPECT_EQ(r.value_weights, m.value_weights);
  // Without colours: the jet colour of the values, grey for none.
  ASSERT_EQ(parsePly(plyBytes(m, {}), &r, &rc, &why), SurfaceStatus::kOk) << why;
  EXPECT_EQ(rc[1], (Rgb8{128, 128, 128}));
  EXPECT_NE(rc[0], rc[3]);
}

TEST(Ply, HostileFilesAreRejected) {
  const Mesh m = twoTriangles();
  const std::string good = plyBytes(m, {});
  Mesh r = twoTriangles();
  std::vector<Rgb8> rc;
  std::string why;
  auto rejects = [&](const std::string& bytes) {
    why.clear();
    const SurfaceStatus st = parsePly(bytes, &r, &rc, &why);
    return st == SurfaceStatus::kParseError && !why.empty();
  };
  EXPECT_TRUE(rejects(good.substr(0, good.size() - 1)));  // truncated last face
  EXPECT_TRUE(rejects(""));
  std::string huge = good;
  huge.replace(huge.find("element vertex 4"), 16, "element vertex 400000000000");
  EXPECT_TRUE(rejects(huge));
  std::string ascii = good;
  ascii.replace(ascii.find("binary_little_endian"), 20, "ascii");
  EXPECT_TRUE(rejects(ascii));
  std::string bad_index = good;
  const std::int32_t nine = 9;
  std::memcpy(&bad_index[bad_index.size() - 4], &nine, 4);
  EXPECT_TRUE(rejects(bad_index));
  // The output is untouched by a rejected file.
  EXPECT_EQ(r.faces, m.faces);
}

TEST(Ply, FileWriteAndRead) {
  const Mesh m = twoTriangles();
  const std::string path = ::testing::TempDir() + "hapi_surface_test.ply";
  ASSERT_EQ(writePly(path, m, {}), SurfaceStatus::kOk);
  Mesh r;
  std::vector<Rgb8> rc;
  std::string why;
  ASSERT_EQ(readPly(path, &r, &rc, &why), SurfaceStatus::kOk) << why;
  EXPECT_EQ(r.faces, m.faces);
  EXPECT_EQ(writePly("/nonexistent-folder/x.ply", m, {}), SurfaceStatus::kIoError);
}

}  // namespace
}  // namespace hapi_surface
