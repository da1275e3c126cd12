#include "hapi_frontend/camera_model.hpp"

#include <Eigen/LU>
#include <opencv2/calib3d.hpp>

#include <cmath>

namespace hapi_frontend {

std::string CameraCalib::validate() const {
  if (width <= 0 || height <= 0) return "image size is zero";
  if (K[0] <= 0 || K[4] <= 0) return "K has zero/negative focal length (uncalibrated camera?)";
  if (P[0] <= 0) return "P has zero focal length";
  for (double v : K) if (!std::isfinite(v)) return "K is not finite";
  for (double v : D) if (!std::isfinite(v)) return "D is not finite";
  if (!D.empty()) {
    if (distortion_model != "plumb_bob" && distortion_model != "rational_polynomial")
      return "unsupported distortion model '" + distortion_model + "'";
    // OpenCV reads 4/5 (plumb_bob) or 8 (rational_polynomial) coefficients;
    // any other length would be silently misinterpreted.
    const size_t n = D.size();
    if (distortion_model == "plumb_bob" && n != 4 && n != 5)
      return "plumb_bob needs 5 distortion coefficients, got " + std::to_string(n);
    if (distortion_model == "rational_polynomial" && n != 8)
      return "rational_polynomial needs 8 distortion coefficients, got " + std::to_string(n);
  }
  return "";
}

CameraModel::CameraModel(const CameraCalib& c, bool rectified_input) {
  if (rectified_input) {
    K_ << c.P[0], c.P[1], c.P[2], c.P[4], c.P[5], c.P[6], c.P[8], c.P[9], c.P[10];
  } else {
    K_ = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c.K.data());
    // plumb_bob has 5 coefficients, rational_polynomial 8: OpenCV reads both layouts.
    if (!c.D.empty()) Dcv_ = cv::Mat(c.D, true).reshape(1, 1);
  }
  Kcv_ = (cv::Mat_<double>(3, 3) << K_(0, 0), K_(0, 1), K_(0, 2), K_(1, 0), K_(1, 1), K_(1, 2), 0, 0, 1);
}

std::vector<Eigen::Vector2d> CameraModel::undistort(const std::vector<cv::Point2f>& px) const {
  std::vector<Eigen::Vector2d> out(px.size());
  if (px.empty()) return out;
  bool any = !Dcv_.empty() && cv::countNonZero(Dcv_ != 0) > 0;
  if (!any) {
    for (size_t i = 0; i < px.size(); ++i) out[i] = {px[i].x, px[i].y};
    return out;
  }
  std::vector<cv::Point2f> und;
  // The default 5 fixed-point iterations leave ~0.1 px error at the image corners
  // of wide lenses; an explicit criterion iterates to convergence.
  cv::undistortPoints(px, und, Kcv_, Dcv_, cv::noArray(), Kcv_,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-6));
  for (size_t i = 0; i < px.size(); ++i) out[i] = {und[i].x, und[i].y};
  return out;
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& u) const {
  std::vector<cv::Point3d> p{{(u.x() - K_(0, 2)) / K_(0, 0), (u.y() - K_(1, 2)) / K_(1, 1), 1.0}};
  std::vector<cv::Point2d> o;
  cv::projectPoints(p, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), Kcv_, Dcv_.empty() ? cv::Mat() : Dcv_, o);
  return {o[0].x, o[0].y};
}

StereoRig StereoRig::fromCalib(const CameraCalib& l, const CameraCalib& r, bool rectified_input) {
  StereoRig rig;
  const double B = -r.P[3] / r.P[0];
  Eigen::Matrix3d Rl = Eigen::Matrix3d::Identity(), Rr = Eigen::Matrix3d::Identity();
  if (!rectified_input) {
    Rl = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(l.R.data());
    Rr = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.R.data());
  }
  rig.R_lr = Rl.transpose() * Rr;
  rig.t_lr = Rl.transpose() * Eigen::Vector3d(B, 0, 0);
  return rig;
}

Eigen::Matrix3d StereoRig::fundamental(const Eigen::Matrix3d& K_l, const Eigen::Matrix3d& K_r) const {
  // p_r = R^T p_l - R^T t  =>  E = [t']x R' with R' = R^T, t' = -R^T t.
  Eigen::Matrix3d Rp = R_lr.transpose();
  Eigen::Vector3d tp = -Rp * t_lr;
  Eigen::Matrix3d tx;
  tx << 0, -tp.z(), tp.y(), tp.z(), 0, -tp.x(), -tp.y(), tp.x(), 0;
  return K_r.inverse().transpose() * (tx * Rp) * K_l.inverse();
}

}  // namespace hapi_frontend
