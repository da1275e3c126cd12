#include "hapi_surface/pinhole_camera.hpp"

#include <cmath>

namespace hapi_surface {

SurfaceStatus PinholeCamera::check() const {
  const bool ok = width > 0 && height > 0 && std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) &&
                  std::isfinite(cy) && fx > 0 && fy > 0 && std::isfinite(k1) && std::isfinite(k2) &&
                  std::isfinite(p1) && std::isfinite(p2) && std::isfinite(k3);
  return ok ? SurfaceStatus::kOk : SurfaceStatus::kBadCamera;
}

bool PinholeCamera::nearView(const Eigen::Vector3d& p) const {
  if (!(p.z() > 0)) return false;
  const double u = fx * p.x() / p.z() + cx, v = fy * p.y() / p.z() + cy;
  return u >= -0.5 * width && u <= 1.5 * width && v >= -0.5 * height && v <= 1.5 * height;
}

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p) const {
  const double x = p.x() / p.z(), y = p.y() / p.z();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  return Eigen::Vector2d(fx * xd + cx, fy * yd + cy);
}

SurfaceStatus checkPose(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return SurfaceStatus::kBadPose;
  const Eigen::Matrix3d R = T.linear();
  if (!(R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || R.determinant() < 0)
    return SurfaceStatus::kBadPose;
  return SurfaceStatus::kOk;
}

double rotationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

double translationBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

}  // namespace hapi_surface
