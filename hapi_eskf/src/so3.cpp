#include "hapi_eskf/so3.hpp"

#include <cmath>

namespace hapi_eskf {

Mat3 skew(const Vec3& v) {
  Mat3 S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// Rodrigues with a Taylor expansion below 1e-8 rad, where 1 - cos and sin/theta
// lose all significant digits.
Mat3 expSO3(const Vec3& phi) {
  const double th2 = phi.squaredNorm();
  const Mat3 K = skew(phi);
  if (th2 < 1e-16) return Mat3::Identity() + K + 0.5 * K * K;
  const double th = std::sqrt(th2);
  return Mat3::Identity() + (std::sin(th) / th) * K + ((1.0 - std::cos(th)) / th2) * K * K;
}

Vec3 logSO3(const Mat3& R) {
  // Through the quaternion: well conditioned on all of SO(3), including near pi.
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Vec3 u = q.vec();
  const double s = u.norm();
  if (s < 1e-12) return 2.0 * u;  // first order, exact to O(|u|^3)
  const double th = 2.0 * std::atan2(s, q.w());
  return (th / s) * u;
}

Mat3 rightJacobianSO3(const Vec3& phi) {
  const double th2 = phi.squaredNorm();
  const Mat3 K = skew(phi);
  if (th2 < 1e-12) return Mat3::Identity() - 0.5 * K + (1.0 / 6.0) * K * K;
  const double th = std::sqrt(th2);
  return Mat3::Identity() - ((1.0 - std::cos(th)) / th2) * K + ((th - std::sin(th)) / (th2 * th)) * K * K;
}

Eigen::Quaterniond quatExp(const Vec3& phi) {
  const double th = phi.norm();
  if (th < 1e-12) {
    Eigen::Quaterniond q(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z());
    return q.normalized();
  }
  const Vec3 a = phi / th;
  const double s = std::sin(0.5 * th);
  return Eigen::Quaterniond(std::cos(0.5 * th), s * a.x(), s * a.y(), s * a.z());
}

bool isRotation(const Mat3& R) {
  return R.allFinite() && (R * R.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-6 &&
         std::abs(R.determinant() - 1.0) < 1e-6;
}

}  // namespace hapi_eskf
