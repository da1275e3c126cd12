// Single-channel float images (depth in metres, confidence, the imaging
// camera's values) and the one conversion of a raw camera buffer (the fields
// of sensor_msgs/Image, without ROS) to such an image.
//
// Unlike hapi_frontend's convertToGrey, which normalises each frame to 8 bit
// for feature tracking, this keeps the physical value: a perfusion map
// (32FC1) is projected in its own units. Encodings: 32FC1 as is (NaN/inf
// kept: a pixel without value), mono8/8UC1 and mono16/16UC1 as their counts,
// rgb8/bgr8/rgba8/bgra8 as Rec. 601 luma (0.299 R + 0.587 G + 0.114 B).
// Big-endian 16-bit and float buffers are byte-swapped.
#pragma once

#include "hapi_surface/surface_status.hpp"

#include <hapi_nodelet_kit/raw_image_view.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hapi_surface {

struct FloatImage {
  int width = 0, height = 0;
  std::vector<float> data;  // row-major, width * height

  bool empty() const { return data.empty(); }
  float at(int u, int v) const { return data[static_cast<std::size_t>(v) * width + u]; }
  float& at(int u, int v) { return data[static_cast<std::size_t>(v) * width + u]; }
};

// A view of a camera buffer (sensor_msgs/Image's fields, hapi_nodelet_kit).
using RawImageView = hapi_nodelet_kit::RawImageView;

// The largest width or height accepted (a guard against absurd headers).
constexpr std::uint32_t kMaxImageSide = 16384;

// *out = the buffer as floats. kUnknownEncoding, kMalformedImage (zero or
// too large a size, a step shorter than a row, a buffer shorter than
// step * height); *out is untouched then.
SurfaceStatus toFloatImage(const RawImageView& image, FloatImage* out);

// *out = the depth confidence (depth_image_contract.hpp) as weights: as
// toFloatImage, a mono8 / 8UC1 image divided by kConfidenceMono8One.
SurfaceStatus toConfidenceImage(const RawImageView& image, FloatImage* out);

// The encodings toFloatImage accepts, as one text for error messages.
const char* floatEncodingsText();

}  // namespace hapi_surface
