// RawImageView: a camera buffer as the fields of sensor_msgs/Image, without
// ROS, so that the ROS-free cores can convert images (hapi_frontend's
// convertToGrey, hapi_surface's toFloatImage) and the nodelets hand them a
// message's buffer without a copy. ROS-free and header-only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace hapi_nodelet_kit {

// `data` must outlive every use of the view.
struct RawImageView {
  std::string encoding;
  std::uint32_t width = 0, height = 0;
  std::uint32_t step = 0;  // bytes per row
  bool bigendian = false;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;  // bytes available at data
};

// The view of a sensor_msgs/Image (any type with its fields: a template, so
// this header needs no ROS).
template <typename ImageMessage>
RawImageView rawView(const ImageMessage& msg) {
  RawImageView v;
  v.encoding = msg.encoding;
  v.width = msg.width;
  v.height = msg.height;
  v.step = msg.step;
  v.bigendian = msg.is_bigendian != 0;
  v.data = msg.data.data();
  v.size = msg.data.size();
  return v;
}

}  // namespace hapi_nodelet_kit
