// Image and match quality measures (image_quality.hpp says what and why).
#include "hapi_frontend/image_quality.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hapi_frontend {
namespace {

}  // namespace

double epipolarOffset(const Eigen::Matrix3d& F, const Eigen::Vector2d& left, const Eigen::Vector2d& right) {
  const Eigen::Vector3d l = F * Eigen::Vector3d(left.x(), left.y(), 1.0);
  const double n = std::hypot(l.x(), l.y());
  if (!(n > 0)) return std::numeric_limits<double>::quiet_NaN();
  // The line's y coefficient fixes the sign: (l . x_r) / l_y = y_r - y_line
  // for a horizontal line.
  const double d = l.dot(Eigen::Vector3d(right.x(), right.y(), 1.0)) / n;
  return l.y() >= 0 ? d : -d;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2) return v[mid];
  const double upper = v[mid];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + mid));
}

double motionBlur(const cv::Mat& grey) {
  constexpr double kMinEnergy = 1.0;  // [grey levels^2 per px^2] below: no gradients to judge
  if (grey.empty() || grey.type() != CV_8UC1) return std::numeric_limits<double>::quiet_NaN();
  cv::Mat half, f, gx, gy;
  cv::pyrDown(grey, half);
  half.convertTo(f, CV_32F);
  cv::Sobel(f, gx, CV_32F, 1, 0, 3);
  cv::Sobel(f, gy, CV_32F, 0, 1, 3);
  const double jxx = cv::mean(gx.mul(gx))[0], jyy = cv::mean(gy.mul(gy))[0], jxy = cv::mean(gx.mul(gy))[0];
  const double half_trace = 0.5 * (jxx + jyy);
  if (!(half_trace > kMinEnergy)) return std::numeric_limits<double>::quiet_NaN();
  // Eigenvalues of the 2x2 symmetric tensor: half_trace +- r.
  const double r = std::hypot(0.5 * (jxx - jyy), jxy);
  return std::min(1.0, std::max(0.0, 1.0 - (half_trace - r) / (half_trace + r)));
}

}  // namespace hapi_frontend
