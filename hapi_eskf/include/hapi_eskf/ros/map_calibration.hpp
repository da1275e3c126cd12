// The stereo calibration a map records and is checked against
// (map_file::MapCalibration), from the rectified pair's CameraInfo messages.
#pragma once

#include "hapi_eskf/map_file/map_data.hpp"

#include <sensor_msgs/CameraInfo.h>

#include <string>

namespace hapi_eskf {
namespace ros_glue {

// The rectified stereo calibration from the two CameraInfo messages: the
// left P (fx, fy, cx, cy), its image size, and the baseline -P_right[3] /
// P_right[0] (REP-104 / image_geometry's StereoCameraModel). False and *why
// when a message does not describe a rectified stereo pair; *out is then
// untouched.
bool toMapCalibration(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right,
                      map_file::MapCalibration* out, std::string* why);

}  // namespace ros_glue
}  // namespace hapi_eskf
