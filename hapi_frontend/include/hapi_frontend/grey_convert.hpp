// One converter from a raw camera buffer (the fields of sensor_msgs/Image,
// without ROS) to the 8-bit grey image the image-flow tracker works on.
// Encodings: mono8 (wrapped, no copy), mono16 (fixed scale
// 255 / (2^mono16_bits - 1), saturated), bgr8, rgb8, bgra8 (luma), 32FC1 (a
// perfusion or other float map: robust per-frame normalisation, the 1st and
// 99th percentiles of the finite values map to 0 and 255; NaN/inf become 0).
// Big-endian mono16/32FC1 buffers are byte-swapped. Bad input returns a
// reason (a diagnostics counter key) and a detail, never throws. ROS-free.
#pragma once

#include "hapi_frontend/input_error.hpp"
#include "hapi_frontend/param_spec.hpp"

#include <hapi_nodelet_kit/raw_image_view.hpp>

#include <opencv2/core.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

namespace hapi_frontend {

// A view of a camera buffer (hapi_nodelet_kit); `data` must outlive every
// image returned without a copy (mono8).
using RawImageView = hapi_nodelet_kit::RawImageView;

// The declaration of the significant bits of mono16 input (the nodelets'
// ~mono16_bits), written once for every reader.
const ParamSpec& mono16BitsSpec();

// The encodings convertToGrey accepts, as one text for error messages.
const char* greyEncodingsText();

// *grey = CV_8UC1 image of the buffer. mono16_bits must satisfy
// mono16BitsSpec() (checked: "invalid_setting"). Reasons: "unsupported_encoding",
// "malformed_image", "conversion_failed".
InputError convertToGrey(const RawImageView& image, int mono16_bits, cv::Mat* grey);

}  // namespace hapi_frontend
