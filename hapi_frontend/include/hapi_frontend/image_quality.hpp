// Two measures of whether a stereo pair is fit for tracking, computed by the
// front end on every frame for the nodelet's self-checks (ROS-free):
//  * the median vertical disparity of the matched keypoints: the signed
//    distance of each right keypoint from its left keypoint's epipolar line,
//    which after rectification is y_right - y_left. A correct calibration
//    leaves only keypoint noise (median ~0.05 px); a wrong one a constant
//    offset that the median reads directly (the matcher still pairs
//    keypoints up to max_epipolar_px off the line).
//  * the motion blur of an image: 1 - lambda_min / lambda_max of the mean
//    gradient structure tensor. Motion during the exposure smears the image
//    along its direction and removes the gradients along it, while the
//    gradients across it stay: an isotropic texture measures ~0 sharp,
//    0.33 smeared over 5 px, 0.64 over 9 px, 0.8 over 15 px. Neither the amount nor the
//    contrast of the texture moves it; a strongly oriented texture (stripes)
//    reads as blurred, which the diagnostic's message says.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <vector>

namespace hapi_frontend {

// Signed distance of the undistorted right pixel `right` from the epipolar
// line F * [left; 1] [px]; positive when the right pixel lies below the line
// (image y down).
double epipolarOffset(const Eigen::Matrix3d& F, const Eigen::Vector2d& left, const Eigen::Vector2d& right);

// Median of `values`; NaN when empty. Takes a copy (nth_element reorders).
double median(std::vector<double> values);

// Motion blur of a CV_8UC1 image in [0, 1]; NaN for an image without
// gradients (uniform). Computed at half resolution, where sensor noise no
// longer dominates the fine gradients.
double motionBlur(const cv::Mat& grey);

}  // namespace hapi_frontend
