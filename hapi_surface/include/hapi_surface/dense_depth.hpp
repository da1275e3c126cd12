// Dense depth of one rectified stereo pair with a per-pixel confidence
// (docs/DESIGN.md "Dense depth"): OpenCV StereoSGBM at 1/16 px, the right
// image matched as well for a left-right consistency check, a texture term,
// and the conversion disparity -> depth z = f b / d. ROS-free.
#pragma once

#include "hapi_surface/dense_depth_settings.hpp"

#include <opencv2/core.hpp>
#include <opencv2/calib3d.hpp>

namespace hapi_surface {

// The rectified left camera of the matched pair (pinhole, no distortion) and
// the baseline: what turns a disparity into a depth.
struct RectifiedGeometry {
  double fx = 0, fy = 0, cx = 0, cy = 0;  // px
  double baseline = 0;                    // m, right camera along +x of the left
  int width = 0, height = 0;              // px
};

// The disparity interval the depth range [min_depth, max_depth] needs at
// focal length f_px and baseline b (DESIGN "Dense depth", search range):
// min_disparity = floor(f b / max_depth), num_disparities the span up to
// ceil(f b / min_depth) rounded up to SGBM's multiple of 16. Requires
// f b / min_depth to fit an int (DenseDepth::compute allows at most the
// image width).
struct DisparitySearch {
  int min_disparity = 0;
  int num_disparities = 16;
};
DisparitySearch disparitySearch(double min_depth, double max_depth, double f_px, double baseline);

struct DepthImage {
  cv::Mat depth;       // CV_32FC1, metres along the optical axis, NaN where invalid
  cv::Mat confidence;  // CV_32FC1 in [0, 1], 0 where depth is NaN
  bool used_gpu = false;  // use_gpu and a CUDA device did the matching
};

class DenseDepth {
 public:
  // Throws std::invalid_argument when settings.validate() fails.
  explicit DenseDepth(const DenseDepthSettings& settings);

  // left, right: the rectified pair, CV_8UC1 of geometry's size. Returns ""
  // or why nothing was computed (sizes or types that do not match, a
  // geometry without focal length or baseline, or one whose depth range
  // needs disparities wider than the image).
  std::string compute(const cv::Mat& left, const cv::Mat& right, const RectifiedGeometry& geometry,
                      DepthImage* out) const;

  const DenseDepthSettings& settings() const { return settings_; }

 private:
  // Disparity (px, float, < search.min_disparity where invalid) of `left`
  // against `right`: SGBM, or with use_gpu the block matcher (*used_gpu
  // set when a CUDA device ran it).
  cv::Mat disparity(const cv::Mat& left, const cv::Mat& right, const DisparitySearch& search, bool* used_gpu) const;
  // SGBM on the images padded on the left, so that pixels near the border
  // are searched over the whole interval too.
  cv::Mat sgbmDisparity(const cv::Mat& left, const cv::Mat& right, const DisparitySearch& search) const;
  // Per-pixel texture term g^2 / (g^2 + g0^2) of the block's mean squared gradient.
  cv::Mat textureTerm(const cv::Mat& left) const;

  DenseDepthSettings settings_;
};

}  // namespace hapi_surface
