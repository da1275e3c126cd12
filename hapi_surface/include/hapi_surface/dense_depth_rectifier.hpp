// Rectification of a raw stereo pair from its two CameraInfo (as ROS's
// stereo_image_proc: K, D, R, P of each camera) onto one common pinhole
// camera, the left projection P_left, scaled by image_scale (docs/DESIGN.md
// "Dense depth", rectification). Rectifying both images onto the same
// intrinsics makes the epipolar lines rows even where the left and right K
// differ (the simulator's rig). ROS-free.
#pragma once

#include "hapi_surface/dense_depth.hpp"

#include <hapi_dataset/camera_info.hpp>

#include <opencv2/core.hpp>

#include <string>

namespace hapi_surface {

using hapi_dataset::CameraInfoData;

class StereoRectifier {
 public:
  // "" when the pair can be rectified, else why not: sizes, a zero K or P,
  // a distortion model other than plumb_bob / rational_polynomial (or none
  // with empty D), a wrong number of coefficients, a right P without a
  // positive baseline (P_right[3] = -fx b).
  static std::string check(const CameraInfoData& left, const CameraInfoData& right);

  // Requires check(left, right) == "" (throws std::invalid_argument otherwise).
  StereoRectifier(const CameraInfoData& left, const CameraInfoData& right, double image_scale);

  // The raw CV_8UC1 images (the CameraInfo's size) -> the rectified, scaled pair.
  void rectify(const cv::Mat& left_raw, const cv::Mat& right_raw, cv::Mat* left, cv::Mat* right) const;

  const RectifiedGeometry& geometry() const { return geometry_; }
  // Whether this rectifier was built from this pair and scale (so a new
  // CameraInfo with the same values needs no new maps).
  bool builtFrom(const CameraInfoData& left, const CameraInfoData& right, double image_scale) const;

 private:
  CameraInfoData left_info_, right_info_;
  double scale_ = 1.0;
  cv::Mat map_lx_, map_ly_, map_rx_, map_ry_;
  RectifiedGeometry geometry_;
};

}  // namespace hapi_surface
