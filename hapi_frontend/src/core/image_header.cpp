// PNG/JPEG header reading (image_header.hpp). Formats: PNG specification
// (ISO/IEC 15948) section 11.2.2 IHDR; JPEG (ITU-T T.81) annex B.
#include "hapi_frontend/image_header.hpp"

#include <cstring>

namespace hapi_frontend {

namespace {

std::uint32_t bigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
std::uint32_t bigEndian16(const std::uint8_t* p) { return (std::uint32_t{p[0]} << 8) | p[1]; }

bool readPng(const std::uint8_t* d, std::size_t n, AnnouncedImage* img, std::string* error) {
  // Signature (8), then the first chunk must be IHDR: length 13, type, data.
  if (n < 8 + 8 + 13) return *error = "truncated PNG header", false;
  if (bigEndian32(d + 8) != 13 || std::memcmp(d + 12, "IHDR", 4) != 0)
    return *error = "PNG without IHDR as first chunk", false;
  const std::uint8_t* h = d + 16;
  img->codec = "png";
  img->width = bigEndian32(h);
  img->height = bigEndian32(h + 4);
  const int depth = h[8];
  // Colour type -> samples per pixel (palette images decode to colour).
  switch (h[9]) {
    case 0: img->channels = 1; break;  // grey
    case 2: img->channels = 3; break;  // RGB
    case 3: img->channels = 3; break;  // palette
    case 4: img->channels = 2; break;  // grey + alpha
    case 6: img->channels = 4; break;  // RGBA
    default: return *error = "PNG colour type " + std::to_string(h[9]) + " is not defined", false;
  }
  if (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16)
    return *error = "PNG bit depth " + std::to_string(depth) + " is not defined", false;
  img->bytes_per_channel = depth == 16 ? 2 : 1;
  return true;
}

bool isStartOfFrame(std::uint8_t marker) {
  // SOF0..SOF15 without DHT (C4), JPG (C8) and DAC (CC).
  return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

bool readJpeg(const std::uint8_t* d, std::size_t n, AnnouncedImage* img, std::string* error) {
  std::size_t i = 2;  // after SOI
  while (i < n) {
    // Bytes before a marker are skipped (libjpeg warns "extraneous bytes"),
    // as are fill bytes 0xFF and stuffed 0xFF 0x00.
    if (d[i] != 0xFF) {
      ++i;
      continue;
    }
    while (i < n && d[i] == 0xFF) ++i;
    if (i >= n) break;
    const std::uint8_t marker = d[i++];
    if (marker == 0x00 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // no length
    if (marker == 0xD8) continue;                                                           // repeated SOI
    if (marker == 0xD9 || marker == 0xDA) return *error = "JPEG without a frame header before its scan", false;
    if (i + 2 > n) break;
    const std::size_t length = bigEndian16(d + i);
    if (length < 2) return *error = "JPEG marker segment of length " + std::to_string(length), false;
    if (isStartOfFrame(marker)) {
      // Lf(2) P(1) Y(2) X(2) Nf(1)
      if (length < 8 || i + 8 > n) break;
      img->codec = "jpeg";
      img->bytes_per_channel = d[i + 2] > 8 ? 2 : 1;
      img->height = bigEndian16(d + i + 3);
      img->width = bigEndian16(d + i + 5);
      img->channels = d[i + 7];
      if (img->channels < 1 || img->channels > 4)
        return *error = "JPEG with " + std::to_string(img->channels) + " components", false;
      return true;
    }
    i += length;
  }
  return *error = "truncated JPEG header (no frame header)", false;
}

}  // namespace

bool readImageHeader(const std::uint8_t* data, std::size_t size, AnnouncedImage* image, std::string* error) {
  *image = AnnouncedImage();
  static const std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  bool ok = false;
  if (size >= 8 && std::memcmp(data, kPng, 8) == 0) {
    ok = readPng(data, size, image, error);
  } else if (size >= 3 && data[0] == 0xFF && data[1] == 0xD8) {
    ok = readJpeg(data, size, image, error);
  } else {
    *error = "neither PNG nor JPEG data";
  }
  if (ok && (image->width == 0 || image->height == 0)) {
    *error = "header announces a " + std::to_string(image->width) + "x" + std::to_string(image->height) + " image";
    ok = false;
  }
  return ok;
}

std::string checkDecodable(const std::uint8_t* data, std::size_t size, std::uint64_t max_decoded_bytes) {
  AnnouncedImage image;
  std::string error;
  if (!readImageHeader(data, size, &image, &error)) return error;
  if (image.decodedBytes() > max_decoded_bytes)
    return image.codec + " header announces " + std::to_string(image.width) + "x" + std::to_string(image.height) +
           "x" + std::to_string(image.channels) + " (" + std::to_string(image.decodedBytes() >> 20) +
           " MiB decoded), more than the " + std::to_string(max_decoded_bytes >> 20) + " MiB limit";
  return "";
}

}  // namespace hapi_frontend
