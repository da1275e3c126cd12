// Conversion of ROS input messages to the core's plain types:
// sensor_msgs/Image -> 8-bit grey (+ BGR colour) and sensor_msgs/CameraInfo
// -> CameraCalib. Every function reports bad input as a (reason, detail) pair
// and never throws, so the nodelet can count it and carry on.
#pragma once

#include "hapi_frontend/camera_model.hpp"
#include "hapi_frontend/input_error.hpp"

#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <string>

namespace hapi_frontend {


struct GreyImage {
  cv::Mat gray;    // CV_8UC1
  cv::Mat colour;  // CV_8UC3 BGR for colour input, empty for mono input
  // Keeps the message alive while gray/colour share its buffer (zero copy for mono8).
  sensor_msgs::ImageConstPtr keep_alive;
};

// Accepted encodings: mono8 (shared, no copy), bgr8, rgb8 (colour kept as
// BGR), mono16 (scaled to 8 bit: v8 = v16 * 255 / (2^mono16_bits - 1),
// saturated). Anything else -> "unsupported_encoding". A buffer shorter than
// step*height or a step shorter than one row -> "malformed_image".
InputError toGrey(const sensor_msgs::ImageConstPtr& msg, int mono16_bits, GreyImage* out);

// Copies the CameraInfo fields used by the core. Rejects (reason
// "invalid_calibration") zero K, an unknown distortion model with non-empty D,
// a wrong number of coefficients, and binning/ROI (not supported by the core).
InputError toCalib(const sensor_msgs::CameraInfo& info, CameraCalib* out);

// The two converted images of a pair have one size, and it is the size their
// CameraInfo messages state ("size_mismatch", "calibration_size_mismatch").
InputError checkPairSizes(const GreyImage& left, const GreyImage& right, const sensor_msgs::CameraInfo& left_info,
                          const sensor_msgs::CameraInfo& right_info);

}  // namespace hapi_frontend
