// The velocity map and its Jacobian (docs/DESIGN.md "Surface motion").
#include "hapi_eskf/surface_motion/velocity_map.hpp"

#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {
namespace surface_motion {
namespace {

constexpr double kMmPerM = 1000.0;

struct Parts {
  Vec3 v, w, e, n, X;
  double d;
};

Parts split(const MapInput& q, const Vec3& ray) {
  Parts p;
  p.v = q.segment<3>(0);
  p.w = q.segment<3>(3);
  p.e = q.segment<3>(6);
  p.d = q(9);
  p.n = q.segment<3>(10);
  p.X = p.d * ray;
  return p;
}

}  // namespace

MapInput mapInput(const Vec3& v, const Vec3& w, const Vec3& e, const RayGeometry& g) {
  MapInput q;
  q << v, w, e, g.depth, g.normal;
  return q;
}

Vec3 materialVelocity(const Vec3& v, const Vec3& w, const Vec3& e, const Vec3& X) { return -(v + w.cross(X)) + e; }

MapOutput evaluateVelocityMap(const MapInput& q, const Vec3& ray, const ImagingCamera& cam) {
  const Parts p = split(q, ray);
  const Vec3 Xd = materialVelocity(p.v, p.w, p.e, p.X);
  const double a = Xd.dot(p.n), b = ray.dot(p.n);
  MapOutput y;
  y.segment<3>(0) = p.X;
  y.segment<3>(3) = Xd - ray * (a / b);
  y(6) = a;
  y.segment<2>(7) = cam.pinholeJacobian(p.X) * Xd;
  return y;
}

MapJacobian velocityMapJacobian(const MapInput& q, const Vec3& ray, const ImagingCamera& cam) {
  const Parts p = split(q, ray);
  const Vec3 Xd = materialVelocity(p.v, p.w, p.e, p.X);
  const double a = Xd.dot(p.n), b = ray.dot(p.n);
  const Vec3 s = Xd - ray * (a / b);

  // dXdot/dq: [-I, [X]x, I, -w x ray, 0].
  Eigen::Matrix<double, 3, kMapInputs> dXd = Eigen::Matrix<double, 3, kMapInputs>::Zero();
  dXd.block<3, 3>(0, 0) = -Mat3::Identity();
  dXd.block<3, 3>(0, 3) = skew(p.X);
  dXd.block<3, 3>(0, 6) = Mat3::Identity();
  dXd.col(9) = -p.w.cross(ray);

  MapJacobian J = MapJacobian::Zero();
  J.block<3, 1>(0, 9) = ray;
  // s = Xd - r (Xd . n) / (r . n): ds/dXd = I - r n^T / b, ds/dn = -r s^T / b.
  J.block<3, kMapInputs>(3, 0) = (Mat3::Identity() - ray * p.n.transpose() / b) * dXd;
  J.block<3, 3>(3, 10) += -ray * s.transpose() / b;
  // vn = Xd . n.
  J.block<1, kMapInputs>(6, 0) = p.n.transpose() * dXd;
  J.block<1, 3>(6, 10) += Xd.transpose();
  // iv = P(X) Xd, P the pinhole Jacobian; its own derivative along X = d ray.
  const Mat23 P = cam.pinholeJacobian(p.X);
  J.block<2, kMapInputs>(7, 0) = P * dXd;
  const double z = p.X.z(), iz2 = 1.0 / (z * z), iz3 = iz2 / z;
  Mat23 dPXd_dX;  // d (P(X) Xd) / dX at fixed Xd
  dPXd_dX << -cam.fx * Xd.z() * iz2, 0, cam.fx * (-Xd.x() * iz2 + 2 * p.X.x() * Xd.z() * iz3),  //
      0, -cam.fy * Xd.z() * iz2, cam.fy * (-Xd.y() * iz2 + 2 * p.X.y() * Xd.z() * iz3);
  J.block<2, 1>(7, 9) += dPXd_dX * ray;
  return J;
}

SurfaceVelocity mapVelocity(const MapInput& q, const MapInputCovariance& Cq, const Vec3& ray,
                            const ImagingCamera& cam) {
  const MapOutput y = evaluateVelocityMap(q, ray, cam);
  const MapJacobian J = velocityMapJacobian(q, ray, cam);
  Eigen::Matrix<double, kMapOutputs, kMapOutputs> Cy = J * Cq * J.transpose();
  Cy = 0.5 * (Cy + Cy.transpose()).eval();
  const double mm2 = kMmPerM * kMmPerM, per_frame = 1.0 / cam.frame_rate;
  SurfaceVelocity out;
  out.point = y.segment<3>(0);
  out.normal = q.segment<3>(10);
  out.surface_velocity = kMmPerM * y.segment<3>(3);
  out.surface_velocity_covariance = mm2 * Cy.block<3, 3>(3, 3);
  out.normal_velocity = kMmPerM * y(6);
  out.normal_velocity_variance = mm2 * Cy(6, 6);
  out.image_velocity = per_frame * y.segment<2>(7);
  out.image_velocity_covariance = per_frame * per_frame * Cy.block<2, 2>(7, 7);
  return out;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
