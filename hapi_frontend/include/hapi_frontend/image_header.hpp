// The size a PNG or JPEG stream announces in its header, read before any
// decoding, and the bound a decoder applies to it.
//
// Why: a few bytes of PNG/JPEG header can announce a gigapixel image, and
// OpenCV's decoders allocate what the header says (their own limit is 2^30
// pixels). A receiver that takes images from the network checks the
// announced size first and refuses what no camera sends, so a hostile or
// broken publisher costs a few microseconds instead of gigabytes.
// ROS-free: plain bytes in, a size out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace hapi_frontend {

struct AnnouncedImage {
  std::string codec;           // "png" or "jpeg"
  std::uint32_t width = 0;     // pixels
  std::uint32_t height = 0;    // pixels
  int channels = 0;            // samples per pixel as decoded (1..4)
  int bytes_per_channel = 0;   // 1 (8-bit or less) or 2 (16-bit, PNG only)

  // Bytes of the decoded image: width * height * channels * bytes_per_channel.
  std::uint64_t decodedBytes() const {
    return static_cast<std::uint64_t>(width) * height * static_cast<std::uint64_t>(channels) * bytes_per_channel;
  }
};

// The largest decoded image accepted: 32 MiB holds a 4K UHD colour frame
// (3840 x 2160 x 3 = 24.9 MB) or 16-bit mono up to 16.7 Mpx, more than any
// camera of this system sends.
constexpr std::uint64_t kMaxDecodedImageBytes = 32ull << 20;

// Reads the PNG IHDR chunk or the JPEG frame header (the first SOFn marker,
// skipping bytes between markers as libjpeg does). Returns false with
// *error for anything else: another format, a truncated or inconsistent
// header, a zero size.
bool readImageHeader(const std::uint8_t* data, std::size_t size, AnnouncedImage* image, std::string* error);

// readImageHeader, then the size bound: "" when a decoder may go ahead,
// otherwise why not.
std::string checkDecodable(const std::uint8_t* data, std::size_t size, std::uint64_t max_decoded_bytes);

}  // namespace hapi_frontend
