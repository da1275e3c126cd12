#include "hapi_eskf/surface_motion/imaging_camera.hpp"

#include <cmath>

namespace hapi_eskf {
namespace surface_motion {

std::string ImagingCamera::check() const {
  const bool finite = std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy) &&
                      std::isfinite(frame_rate);
  if (!finite) return "the imaging camera's intrinsics are not finite";
  for (double d : distortion)
    if (!std::isfinite(d)) return "the imaging camera's distortion is not finite";
  if (fx <= 0 || fy <= 0) return "the imaging camera's focal lengths must be > 0";
  if (width <= 0 || height <= 0) return "the imaging camera's image size must be > 0";
  if (frame_rate <= 0) return "the imaging camera's frame rate must be > 0";
  return "";
}

Vec2 ImagingCamera::pixel(double u, double v) const {
  return Vec2(u < 0 ? 0.5 * (width - 1) : u, v < 0 ? 0.5 * (height - 1) : v);
}

Vec2 ImagingCamera::distort(const Vec2& xn) const {
  const double x = xn.x(), y = xn.y(), r2 = x * x + y * y;
  const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3], k3 = distortion[4];
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return Vec2(x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
              y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y);
}

Mat2 ImagingCamera::distortJacobian(const Vec2& xn) const {
  const double x = xn.x(), y = xn.y(), r2 = x * x + y * y;
  const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3], k3 = distortion[4];
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double dradial = k1 + r2 * (2 * k2 + 3 * r2 * k3);  // d radial / d r2
  Mat2 J;
  J(0, 0) = radial + 2 * x * x * dradial + 2 * p1 * y + 6 * p2 * x;
  J(0, 1) = 2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y;
  J(1, 0) = 2 * x * y * dradial + 2 * p1 * x + 2 * p2 * y;
  J(1, 1) = radial + 2 * y * y * dradial + 6 * p1 * y + 2 * p2 * x;
  return J;
}

Vec2 ImagingCamera::undistort(const Vec2& px) const {
  const Vec2 xd((px.x() - cx) / fx, (px.y() - cy) / fy);
  // Newton on distort(x) = xd from x = xd: converges in a few steps wherever
  // the distortion is monotonic (the image).
  Vec2 x = xd;
  for (int i = 0; i < 20; ++i) {
    const Vec2 r = distort(x) - xd;
    if (r.norm() < 1e-14) break;
    x -= distortJacobian(x).lu().solve(r);
  }
  return x;
}

Vec3 ImagingCamera::ray(const Vec2& px) const {
  const Vec2 x = undistort(px);
  return Vec3(x.x(), x.y(), 1.0).normalized();
}

Vec2 ImagingCamera::project(const Vec3& X) const {
  const Vec2 xd = distort(Vec2(X.x() / X.z(), X.y() / X.z()));
  return Vec2(fx * xd.x() + cx, fy * xd.y() + cy);
}

Mat23 ImagingCamera::projectJacobian(const Vec3& X) const {
  const double iz = 1.0 / X.z();
  Mat23 dn;  // d (x/z, y/z) / dX
  dn << iz, 0, -X.x() * iz * iz, 0, iz, -X.y() * iz * iz;
  const Mat2 Dd = distortJacobian(Vec2(X.x() * iz, X.y() * iz));
  return Eigen::DiagonalMatrix<double, 2>(fx, fy) * Dd * dn;
}

Vec2 ImagingCamera::projectPinhole(const Vec3& X) const {
  return Vec2(fx * X.x() / X.z() + cx, fy * X.y() / X.z() + cy);
}

Mat23 ImagingCamera::pinholeJacobian(const Vec3& X) const {
  const double iz = 1.0 / X.z();
  Mat23 J;
  J << fx * iz, 0, -fx * X.x() * iz * iz, 0, fy * iz, -fy * X.y() * iz * iz;
  return J;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
