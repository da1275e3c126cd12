#include "hapi_surface/float_image.hpp"

#include "hapi_surface/depth_image_contract.hpp"

#include <cstring>

namespace hapi_surface {
namespace {

enum class Layout { kU8, kU16, kF32, kRgb, kBgr, kRgba, kBgra, kUnknown };

Layout layoutOf(const std::string& e) {
  if (e == "mono8" || e == "8UC1") return Layout::kU8;
  if (e == "mono16" || e == "16UC1") return Layout::kU16;
  if (e == "32FC1") return Layout::kF32;
  if (e == "rgb8") return Layout::kRgb;
  if (e == "bgr8") return Layout::kBgr;
  if (e == "rgba8") return Layout::kRgba;
  if (e == "bgra8") return Layout::kBgra;
  return Layout::kUnknown;
}

std::size_t bytesPerPixel(Layout l) {
  switch (l) {
    case Layout::kU8: return 1;
    case Layout::kU16: return 2;
    case Layout::kF32: return 4;
    case Layout::kRgb: case Layout::kBgr: return 3;
    case Layout::kRgba: case Layout::kBgra: return 4;
    case Layout::kUnknown: break;
  }
  return 0;
}

// A little-endian host reading a buffer of the given byte order.
template <typename T>
T load(const std::uint8_t* p, bool bigendian) {
  std::uint8_t b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = bigendian ? p[sizeof(T) - 1 - i] : p[i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

float luma(float r, float g, float b) { return 0.299f * r + 0.587f * g + 0.114f * b; }

float pixel(Layout l, const std::uint8_t* p, bool bigendian) {
  switch (l) {
    case Layout::kU8: return p[0];
    case Layout::kU16: return load<std::uint16_t>(p, bigendian);
    case Layout::kF32: return load<float>(p, bigendian);
    case Layout::kRgb: case Layout::kRgba: return luma(p[0], p[1], p[2]);
    case Layout::kBgr: case Layout::kBgra: return luma(p[2], p[1], p[0]);
    case Layout::kUnknown: break;
  }
  return 0.f;
}

}  // namespace

const char* floatEncodingsText() { return "32FC1, mono8, 8UC1, mono16, 16UC1, rgb8, bgr8, rgba8, bgra8"; }

SurfaceStatus toFloatImage(const RawImageView& image, FloatImage* out) {
  const Layout l = layoutOf(image.encoding);
  if (l == Layout::kUnknown) return SurfaceStatus::kUnknownEncoding;
  const std::size_t bpp = bytesPerPixel(l);
  const std::size_t w = image.width, h = image.height;
  if (w == 0 || h == 0 || w > kMaxImageSide || h > kMaxImageSide || image.data == nullptr)
    return SurfaceStatus::kMalformedImage;
  if (image.step < w * bpp || image.size / image.step < h) return SurfaceStatus::kMalformedImage;
  FloatImage f;
  f.width = static_cast<int>(w);
  f.height = static_cast<int>(h);
  f.data.resize(w * h);
  for (std::size_t v = 0; v < h; ++v) {
    const std::uint8_t* row = image.data + v * image.step;
    for (std::size_t u = 0; u < w; ++u) f.data[v * w + u] = pixel(l, row + u * bpp, image.bigendian);
  }
  *out = std::move(f);
  return SurfaceStatus::kOk;
}

SurfaceStatus toConfidenceImage(const RawImageView& image, FloatImage* out) {
  const SurfaceStatus st = toFloatImage(image, out);
  if (st != SurfaceStatus::kOk || layoutOf(image.encoding) != Layout::kU8) return st;
  for (float& c : out->data) c /= static_cast<float>(kConfidenceMono8One);
  return st;
}

}  // namespace hapi_surface
