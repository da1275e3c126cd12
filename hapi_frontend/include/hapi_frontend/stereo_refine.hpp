// Sub-pixel refinement of a stereo match: the left keypoint's patch is
// searched for in the right image around the matched right keypoint (ZNCC,
// 2D integer search + parabola fit per axis). Detector keypoints are
// quantised to their pyramid level's pixel grid (up to 1.7 px at level 3);
// aligning the right patch to the left one makes the disparity -- hence the
// depth -- accurate to a fraction of a pixel, and a low or off-centre
// correlation peak rejects wrong matches. Works on raw (distorted) images:
// over an 11x11 patch the distortion is a negligible local warp.
#pragma once

#include <opencv2/core.hpp>

namespace hapi_frontend {

struct RefineParams {
  int half_patch = 5;      // patch (2h+1)^2 [px], h <= 30
  int radius = 3;          // integer search +- radius around the right keypoint [px], <= 30
  double min_zncc = 0.8;   // correlation peak below this -> match rejected
};

struct RefineResult {
  bool ok = false;
  cv::Point2f right;       // refined right pixel (raw image coordinates)
  double zncc = 0.0;
};

// left/right: CV_8UC1 full-resolution grey images.
RefineResult refineStereoMatch(const cv::Mat& left, const cv::Mat& right, const cv::Point2f& pl,
                               const cv::Point2f& pr, const RefineParams& p);

}  // namespace hapi_frontend
