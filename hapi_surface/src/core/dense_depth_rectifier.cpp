// StereoRectifier (dense_depth_rectifier.hpp); docs/DESIGN.md "Dense depth",
// rectification.
#include "hapi_surface/dense_depth_rectifier.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

namespace hapi_surface {
namespace {

std::string checkCamera(const CameraInfoData& c, const char* which) {
  const std::string w = which;
  if (c.width <= 0 || c.height <= 0) return w + " camera_info has no image size";
  if (c.K[0] <= 0 || c.K[4] <= 0 || c.P[0] <= 0 || c.P[5] <= 0) return w + " camera_info has a zero K or P";
  const std::size_t n = c.D.size();
  if (c.distortion_model == "plumb_bob" || c.distortion_model == "rational_polynomial") {
    if (n != 0 && n != 4 && n != 5 && n != 8) return w + " camera_info: " + std::to_string(n) + " distortion coefficients";
  } else if (!(c.distortion_model.empty() && n == 0)) {
    return w + " camera_info: distortion model '" + c.distortion_model + "' is not supported";
  }
  return "";
}

cv::Mat projection3x3(const CameraInfoData& c) {
  return (cv::Mat_<double>(3, 3) << c.P[0], c.P[1], c.P[2], c.P[4], c.P[5], c.P[6], c.P[8], c.P[9], c.P[10]);
}

void buildMaps(const CameraInfoData& c, const cv::Mat& new_k, cv::Mat* mx, cv::Mat* my) {
  const cv::Mat k(3, 3, CV_64F, const_cast<double*>(c.K.data()));
  const cv::Mat r(3, 3, CV_64F, const_cast<double*>(c.R.data()));
  const cv::Mat d(c.D, true);
  const bool no_rotation = cv::countNonZero(r) == 0;  // an all-zero R: the camera is not rotated
  cv::initUndistortRectifyMap(k, d, no_rotation ? cv::Mat::eye(3, 3, CV_64F) : r, new_k,
                              cv::Size(c.width, c.height), CV_32FC1, *mx, *my);
}

bool sameInfo(const CameraInfoData& a, const CameraInfoData& b) {
  return a.width == b.width && a.height == b.height && a.distortion_model == b.distortion_model && a.D == b.D &&
         a.K == b.K && a.R == b.R && a.P == b.P;
}

}  // namespace

std::string StereoRectifier::check(const CameraInfoData& left, const CameraInfoData& right) {
  std::string e = checkCamera(left, "left");
  if (e.empty()) e = checkCamera(right, "right");
  if (!e.empty()) return e;
  if (left.width != right.width || left.height != right.height) return "left and right camera_info differ in size";
  if (!(-right.P[3] / right.P[0] > 0)) return "right camera_info P has no positive baseline (P[3] = -fx b)";
  return "";
}

StereoRectifier::StereoRectifier(const CameraInfoData& left, const CameraInfoData& right, double image_scale)
    : left_info_(left), right_info_(right), scale_(image_scale) {
  const std::string e = check(left, right);
  if (!e.empty()) throw std::invalid_argument("StereoRectifier: " + e);
  if (!(image_scale > 0 && image_scale <= 1)) throw std::invalid_argument("StereoRectifier: image_scale out of (0, 1]");
  // Both images onto the left projection (the header's why).
  const cv::Mat p = projection3x3(left);
  buildMaps(left, p, &map_lx_, &map_ly_);
  buildMaps(right, p, &map_rx_, &map_ry_);
  RectifiedGeometry& g = geometry_;
  g.width = static_cast<int>(std::lround(left.width * image_scale));
  g.height = static_cast<int>(std::lround(left.height * image_scale));
  const double sx = static_cast<double>(g.width) / left.width, sy = static_cast<double>(g.height) / left.height;
  // Area resampling maps pixel centres as u' + 0.5 = s (u + 0.5).
  g.fx = left.P[0] * sx;
  g.fy = left.P[5] * sy;
  g.cx = (left.P[2] + 0.5) * sx - 0.5;
  g.cy = (left.P[6] + 0.5) * sy - 0.5;
  g.baseline = -right.P[3] / right.P[0];
}

void StereoRectifier::rectify(const cv::Mat& left_raw, const cv::Mat& right_raw, cv::Mat* left,
                              cv::Mat* right) const {
  cv::Mat l, r;
  cv::remap(left_raw, l, map_lx_, map_ly_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  cv::remap(right_raw, r, map_rx_, map_ry_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  const cv::Size size(geometry_.width, geometry_.height);
  if (size == l.size()) {
    *left = l;
    *right = r;
    return;
  }
  cv::resize(l, *left, size, 0, 0, cv::INTER_AREA);
  cv::resize(r, *right, size, 0, 0, cv::INTER_AREA);
}

bool StereoRectifier::builtFrom(const CameraInfoData& left, const CameraInfoData& right, double image_scale) const {
  return image_scale == scale_ && sameInfo(left, left_info_) && sameInfo(right, right_info_);
}

}  // namespace hapi_surface
