// The surface as OBJ + MTL + PNG atlas (textured_obj.hpp): written, read
// back with a parser of its own (OBJ lines, PNG chunks with their CRCs, the
// zlib stream with its Adler-32), and the texture at each triangle corner's
// texture coordinates is the colour of that vertex's value; between them
// the colours are blended.
#include "hapi_surface/png_io.hpp"
#include "hapi_surface/textured_obj.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace hapi_surface {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::uint32_t bigEndian(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(s[at + k]);
  return v;
}

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb8> rgb;
};

// A PNG of 8-bit RGB, filter None, its IDAT a zlib stream of stored blocks
// (what pngBytes writes); any other form fails the test.
Image decodePng(const std::string& png) {
  Image im;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::string idat;
  for (std::size_t at = 8; at + 12 <= png.size();) {
    const std::uint32_t len = bigEndian(png, at);
    const std::string type = png.substr(at + 4, 4);
    const std::string body = png.substr(at + 4, 4 + len);
    EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(body.data()), body.size()), bigEndian(png, at + 8 + len))
        << type;
    if (type == "IHDR") {
      im.width = static_cast<int>(bigEndian(png, at + 8));
      im.height = static_cast<int>(bigEndian(png, at + 12));
      EXPECT_EQ(png.substr(at + 16, 5), std::string("\x08\x02\x00\x00\x00", 5));
    } else if (type == "IDAT") {
      idat += png.substr(at + 8, len);
    }
    at += 12 + len;
  }
  EXPECT_EQ((static_cast<unsigned char>(idat[0]) * 256 + static_cast<unsigned char>(idat[1])) % 31, 0);
  std::string raw;
  for (std::size_t at = 2;;) {
    const unsigned char head = static_cast<unsigned char>(idat[at]);
    EXPECT_EQ(head & 6u, 0u) << "not a stored block";
    const std::size_t n = static_cast<unsigned char>(idat[at + 1]) | (static_cast<unsigned char>(idat[at + 2]) << 8);
    raw += idat.substr(at + 5, n);
    at += 5 + n;
    if (head & 1u) {
      EXPECT_EQ(adler32(reinterpret_cast<const std::uint8_t*>(raw.data()), raw.size()), bigEndian(idat, at));
      break;
    }
  }
  const std::size_t row = 1 + 3 * static_cast<std::size_t>(im.width);
  EXPECT_EQ(raw.size(), row * im.height);
  for (int y = 0; y < im.height; ++y) {
    EXPECT_EQ(raw[y * row], 0);
    for (int x = 0; x < im.width; ++x) {
      const char* p = &raw[y * row + 1 + 3 * x];
      im.rgb.push_back({static_cast<std::uint8_t>(p[0]), static_cast<std::uint8_t>(p[1]), static_cast<std::uint8_t>(p[2])});
    }
  }
  return im;
}

struct Obj {
  std::vector<Eigen::Vector3f> v, vn;
  std::vector<Eigen::Vector2f> vt;
  std::vector<std::array<std::array<int, 3>, 3>> f;  // per corner: v, vt, vn (0-based)
  std::string mtllib, usemtl;
};

Obj parseObj(const std::string& text) {
  Obj o;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string key;
    l >> key;
    if (key == "v" || key == "vn") {
      Eigen::Vector3f p;
      l >> p.x() >> p.y() >> p.z();
      (key == "v" ? o.v : o.vn).push_back(p);
    } else if (key == "vt") {
      Eigen::Vector2f t;
      l >> t.x() >> t.y();
      o.vt.push_back(t);
    } else if (key == "f") {
      std::array<std::array<int, 3>, 3> face{};
      for (auto& c : face) {
        std::string s;
        l >> s;
        EXPECT_EQ(std::sscanf(s.c_str(), "%d/%d/%d", &c[0], &c[1], &c[2]), 3) << s;
        for (int& i : c) --i;
      }
      o.f.push_back(face);
    } else if (key == "mtllib") {
      l >> o.mtllib;
    } else if (key == "usemtl") {
      l >> o.usemtl;
    }
  }
  return o;
}

// The texel under texture coordinates (OBJ: v = 0 at the bottom row).
Rgb8 texel(const Image& im, const Eigen::Vector2f& uv) {
  const int x = static_cast<int>(std::floor(uv.x() * im.width));
  const int y = static_cast<int>(std::floor((1.0f - uv.y()) * im.height));
  return im.rgb[static_cast<std::size_t>(y) * im.width + x];
}

// A fan of 7 triangles around a centre vertex, values 0 .. 70 at the rim.
Mesh fan() {
  Mesh m;
  m.vertices.push_back({0, 0, 0.25f});
  m.values.push_back(35);
  for (int k = 0; k < 8; ++k) {
    const float a = 0.8f * k;
    m.vertices.push_back({0.01f * std::cos(a), 0.01f * std::sin(a), 0.25f});
    m.values.push_back(10.0f * k);
  }
  for (int k = 1; k < 8; ++k) m.faces.push_back({0, k, k + 1});
  m.normals.assign(m.vertices.size(), Eigen::Vector3f(0, 0, -1));
  return m;
}

TEST(TexturedObj, TextureHoldsEachVertexsColour) {
  const Mesh m = fan();
  std::vector<Rgb8> colours;
  for (float v : m.values) colours.push_back(jetColour(v, 0, 70));
  char dir[] = "/tmp/hapi_obj_XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string obj_path = std::string(dir) + "/skin.obj";
  ASSERT_EQ(writeTexturedObj(obj_path, m, colours), SurfaceStatus::kOk);

  const Obj o = parseObj(readFile(obj_path));
  EXPECT_EQ(o.mtllib, "skin.mtl");
  EXPECT_EQ(o.usemtl, "surface");
  ASSERT_EQ(o.v.size(), m.vertices.size());
  ASSERT_EQ(o.vn.size(), m.vertices.size());
  ASSERT_EQ(o.f.size(), m.faces.size());
  const std::string mtl = readFile(std::string(dir) + "/skin.mtl");
  EXPECT_NE(mtl.find("newmtl surface\n"), std::string::npos);
  EXPECT_NE(mtl.find("map_Kd skin.png\n"), std::string::npos);
  const Image im = decodePng(readFile(std::string(dir) + "/skin.png"));
  ASSERT_GT(im.width, 0);

  for (std::size_t f = 0; f < o.f.size(); ++f) {
    std::array<Rgb8, 3> corner;
    for (int k = 0; k < 3; ++k) {
      const auto& c = o.f[f][k];
      ASSERT_EQ(c[0], m.faces[f][k]);
      EXPECT_LT((o.v[c[0]] - m.vertices[c[0]]).norm(), 1e-6f);
      const Eigen::Vector2f uv = o.vt[c[1]];
      ASSERT_TRUE(uv.x() > 0 && uv.x() < 1 && uv.y() > 0 && uv.y() < 1);
      corner[k] = texel(im, uv);
      EXPECT_EQ(corner[k], colours[c[0]]) << "face " << f << " corner " << k;
    }
    // The texel one step along the first edge blends the two ends' colours
    // (1/3 of the way in a 4-texel cell).
    const Eigen::Vector2f uv0 = o.vt[o.f[f][0][1]], uv1 = o.vt[o.f[f][1][1]];
    const Rgb8 third = texel(im, uv0 + (uv1 - uv0) / 3.0f);
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(third[ch], (2.0 * colours[m.faces[f][0]][ch] + colours[m.faces[f][1]][ch]) / 3.0, 0.51);
  }
  for (const char* ext : {".obj", ".mtl", ".png"}) std::remove((std::string(dir) + "/skin" + ext).c_str());
  rmdir(dir);
}

TEST(TexturedObj, BadInputIsAnError) {
  const Mesh m = fan();
  const std::vector<Rgb8> colours(m.vertices.size(), Rgb8{1, 2, 3});
  EXPECT_EQ(writeTexturedObj("/nonexistent-folder/skin.obj", m, colours), SurfaceStatus::kIoError);
  EXPECT_EQ(writeTexturedObj("/tmp/skin.obj", m, {}), SurfaceStatus::kSizeMismatch);
  EXPECT_EQ(writeTexturedObj("/tmp/skin.obj", Mesh(), {}), SurfaceStatus::kNoVolume);
  EXPECT_TRUE(isObjPath("/a/b.OBJ"));
  EXPECT_FALSE(isObjPath("/a/b.ply"));
  EXPECT_TRUE(pngBytes(2, 2, std::vector<Rgb8>(3)).empty());
}

TEST(Png, KnownChecksums) {
  // zlib's and PNG's reference values.
  const std::string s = "123456789";
  EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), 0xCBF43926u);
  EXPECT_EQ(adler32(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()), 0x091E01DEu);
}

}  // namespace
}  // namespace hapi_surface
