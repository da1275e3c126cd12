#include "hapi_surface/png_io.hpp"

#include <algorithm>
#include <array>

namespace hapi_surface {
namespace {

void putBigEndian(std::string* out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out->push_back(static_cast<char>((v >> s) & 0xFFu));
}

void chunk(std::string* out, const char type[4], const std::string& data) {
  putBigEndian(out, static_cast<std::uint32_t>(data.size()));
  std::string body(type, 4);
  body += data;
  out->append(body);
  putBigEndian(out, crc32(reinterpret_cast<const std::uint8_t*>(body.data()), body.size()));
}

// A zlib stream of `raw` in stored blocks of at most 65535 bytes.
std::string storedZlib(const std::string& raw) {
  std::string z;
  z.push_back(static_cast<char>(0x78));  // deflate, 32 K window
  z.push_back(static_cast<char>(0x01));  // no preset dictionary; (0x78 * 256 + 0x01) % 31 == 0
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + n == raw.size();
    z.push_back(static_cast<char>(last ? 1 : 0));  // BFINAL, BTYPE 00 (stored)
    const std::uint16_t len = static_cast<std::uint16_t>(n), nlen = static_cast<std::uint16_t>(~len);
    z.push_back(static_cast<char>(len & 0xFF));
    z.push_back(static_cast<char>(len >> 8));
    z.push_back(static_cast<char>(nlen & 0xFF));
    z.push_back(static_cast<char>(nlen >> 8));
    z.append(raw, pos, n);
    pos += n;
  } while (pos < raw.size());
  putBigEndian(&z, adler32(reinterpret_cast<const std::uint8_t*>(raw.data()), raw.size()));
  return z;
}

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = c & 1u ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

std::uint32_t adler32(const std::uint8_t* data, std::size_t n) {
  std::uint32_t a = 1, b = 0;
  for (std::size_t i = 0; i < n; ++i) {
    a = (a + data[i]) % 65521u;
    b = (b + a) % 65521u;
  }
  return (b << 16) | a;
}

std::string pngBytes(int width, int height, const std::vector<Rgb8>& rgb) {
  if (width <= 0 || height <= 0 || rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    return "";
  std::string raw;
  raw.reserve(static_cast<std::size_t>(height) * (1 + 3 * static_cast<std::size_t>(width)));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter type None
    for (int x = 0; x < width; ++x)
      for (std::uint8_t c : rgb[static_cast<std::size_t>(y) * width + x]) raw.push_back(static_cast<char>(c));
  }
  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  putBigEndian(&header, static_cast<std::uint32_t>(width));
  putBigEndian(&header, static_cast<std::uint32_t>(height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
  chunk(&png, "IHDR", header);
  chunk(&png, "IDAT", storedZlib(raw));
  chunk(&png, "IEND", "");
  return png;
}

}  // namespace hapi_surface
