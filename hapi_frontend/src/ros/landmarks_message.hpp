// Core result -> hapi_msgs/StereoLandmarks (field meanings and units are
// documented in hapi_msgs/msg/StereoLandmarks.msg and StereoLandmark.msg).
#pragma once

#include "hapi_frontend/stereo_pipeline.hpp"

#include <hapi_msgs/StereoLandmarks.h>
#include <std_msgs/Header.h>

#include <string>

namespace hapi_frontend {

// Fills every field of *msg. Returns a non-empty reason when the core result
// is internally inconsistent (descriptor rows != landmarks, non-finite
// values), in which case nothing must be published.
std::string fillLandmarksMsg(const StereoFrameResult& result, const std_msgs::Header& header,
                             hapi_msgs::StereoLandmarks* msg);

}  // namespace hapi_frontend
