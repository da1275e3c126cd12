// The image-flow tracker's ROS edges: a sensor_msgs/Image seen as the core's
// RawImageView (no copy), and an ImageFlowResult as hapi_msgs/ImageFlow.
#pragma once

#include "hapi_frontend/grey_convert.hpp"
#include "hapi_frontend/image_flow_tracker.hpp"

#include <hapi_msgs/ImageFlow.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

namespace hapi_frontend {

// A view of msg's buffer: valid while msg lives (hapi_nodelet_kit).
using hapi_nodelet_kit::rawView;

// header: the image's (stamp = the later frame, frame_id = its optical frame).
void fillFlowMsg(const ImageFlowResult& result, const std_msgs::Header& header, hapi_msgs::ImageFlow* msg);

}  // namespace hapi_frontend
