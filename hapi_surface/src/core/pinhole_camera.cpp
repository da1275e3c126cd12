#include "hapi_surface/pinhole_camera.hpp"

#include <cmath>

namespace hapi_surface {

SurfaceStatus PinholeCamera::check() const {
  const bool ok = width > 0 && height > 0 && std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) &&
                  std::isfinite(cy) && fx > 0 && fy > 0;
  return ok ? SurfaceStatus::kOk : SurfaceStatus::kBadCamera;
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
