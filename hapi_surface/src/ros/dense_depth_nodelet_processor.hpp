// One depth keyframe from ROS messages to ROS messages, shared by
// DenseDepthNodelet and dense_depth_link: the front end's image conversion
// (hapi_frontend::toGrey, its encodings and checks), the CameraInfo pair ->
// rectifier (rebuilt only when the pair changes), the matcher, and the
// output messages: depth 32FC1 in metres (NaN invalid, REP-118), confidence
// mono8 (255 = 1), and the depth image's CameraInfo (the rectified, scaled
// left projection, no distortion), each with the left image's header.
#pragma once

#include "dense_depth_nodelet_params.hpp"

#include "hapi_frontend/input_error.hpp"
#include "hapi_surface/dense_depth.hpp"
#include "hapi_surface/dense_depth_rectifier.hpp"

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <memory>

namespace hapi_surface {

using hapi_frontend::InputError;

struct DepthMessages {
  sensor_msgs::ImagePtr depth, confidence;
  sensor_msgs::CameraInfoPtr camera_info;
  double valid_fraction = 0;  // of the depth image's pixels
};

class DenseDepthProcessor {
 public:
  // params.depth must be valid (readDenseDepthParams checked it).
  explicit DenseDepthProcessor(const DenseDepthNodeletParams& params);

  // Reasons: the front end's ("unsupported_encoding", "malformed_image",
  // "size_mismatch", "calibration_size_mismatch"), "missing_frame_id",
  // "invalid_calibration", "core_rejected".
  InputError process(const sensor_msgs::ImageConstPtr& left, const sensor_msgs::CameraInfoConstPtr& left_info,
                     const sensor_msgs::ImageConstPtr& right, const sensor_msgs::CameraInfoConstPtr& right_info,
                     DepthMessages* out);

 private:
  InputError updateRectifier(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right);

  DenseDepthNodeletParams params_;
  DenseDepth matcher_;
  std::unique_ptr<StereoRectifier> rectifier_;
};

// The plain mirror of a CameraInfo message.
CameraInfoData toCameraInfoData(const sensor_msgs::CameraInfo& msg);

}  // namespace hapi_surface
