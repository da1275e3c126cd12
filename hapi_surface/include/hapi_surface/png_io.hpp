// An 8-bit RGB PNG written without a compression library: the image data
// in stored (uncompressed) deflate blocks, which every PNG reader takes
// (RFC 1950/1951, PNG 1.2). Larger than a compressed file, but the core
// stays free of dependencies beyond Eigen.
#pragma once

#include "hapi_surface/colour_map.hpp"
#include "hapi_surface/surface_status.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hapi_surface {

// The bytes of a width x height PNG of `rgb` (row-major, top row first);
// empty when the sizes disagree or are not positive.
std::string pngBytes(int width, int height, const std::vector<Rgb8>& rgb);

// CRC-32 (ISO 3309, the one of PNG chunks) and Adler-32 (zlib) of bytes.
std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0);
std::uint32_t adler32(const std::uint8_t* data, std::size_t n);

}  // namespace hapi_surface
