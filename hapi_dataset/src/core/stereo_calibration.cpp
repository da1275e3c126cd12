// CameraInfo pair of an unrectified stereo rig (stereo_calibration.hpp);
// docs/DESIGN.md "Dataset calibration".
#include "hapi_dataset/stereo_calibration.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <stdexcept>

namespace hapi_dataset {
namespace {

cv::Matx33d cameraMatrix(const CameraSensor& c) {
  return cv::Matx33d(c.fu, 0, c.cu, 0, c.fv, c.cv, 0, 0, 1);
}

// plumb_bob: k1 k2 p1 p2 k3, radial-tangential has no k3.
std::vector<double> plumbBob(const CameraSensor& c) {
  return {c.distortion.at(0), c.distortion.at(1), c.distortion.at(2), c.distortion.at(3), 0.0};
}

CameraInfoData info(const CameraSensor& c, const cv::Mat& R, const cv::Mat& P) {
  CameraInfoData d;
  d.width = c.width;
  d.height = c.height;
  d.D = plumbBob(c);
  const cv::Matx33d K = cameraMatrix(c);
  for (int i = 0; i < 9; ++i) d.K[i] = K.val[i];
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) d.R[3 * r + k] = R.at<double>(r, k);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) d.P[4 * r + k] = P.at<double>(r, k);
  return d;
}

}  // namespace

StereoCalibration rectifyStereo(const CameraSensor& left, const CameraSensor& right) {
  if (left.width != right.width || left.height != right.height)
    throw std::invalid_argument("stereo cameras differ in resolution");
  StereoCalibration out;
  out.T_left_right = left.T_BS.inverse() * right.T_BS;
  out.baseline = out.T_left_right.translation().norm();
  if (!(out.baseline > 1e-6)) throw std::invalid_argument("stereo cameras coincide (no baseline)");

  // stereoRectify takes the transform from the first to the second camera:
  // x_right = R x_left + T, i.e. T_right_left.
  const Eigen::Isometry3d T_rl = out.T_left_right.inverse();
  cv::Mat R(3, 3, CV_64F), T(3, 1, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R.at<double>(r, c) = T_rl.linear()(r, c);
    T.at<double>(r) = T_rl.translation()(r);
  }
  const cv::Mat K1(cameraMatrix(left)), K2(cameraMatrix(right));
  // copyData: the vectors are temporaries.
  const cv::Mat D1(plumbBob(left), true), D2(plumbBob(right), true);
  cv::Mat R1, R2, P1, P2, Q;
  // camera_calibration's defaults: zero disparity at infinity
  // (CALIB_ZERO_DISPARITY), alpha 0 (only valid pixels), same image size.
  cv::stereoRectify(K1, D1, K2, D2, cv::Size(left.width, left.height), R, T, R1, R2, P1, P2, Q,
                    cv::CALIB_ZERO_DISPARITY, 0.0, cv::Size(left.width, left.height));
  out.left = info(left, R1, P1);
  out.right = info(right, R2, P2);
  return out;
}

}  // namespace hapi_dataset
