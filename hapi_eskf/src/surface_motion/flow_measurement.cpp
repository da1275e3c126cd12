#include "hapi_eskf/surface_motion/flow_measurement.hpp"

#include <Eigen/Cholesky>

#include <cmath>

namespace hapi_eskf {
namespace surface_motion {

Mat2 FlowMeasurement::displacementCovariance() const {
  Mat2 C;
  C << covariance[0], covariance[1], covariance[6], covariance[7];
  return C;
}

std::string checkFlow(const FlowMeasurement& f, double min_interval, double max_interval) {
  if (f.status != FlowMeasurement::kOk) return "status " + std::to_string(f.status) + " (no valid flow)";
  if (!std::isfinite(f.t) || !std::isfinite(f.t_prev) || !std::isfinite(f.u) || !std::isfinite(f.v))
    return "non-finite stamp or pixel";
  for (double a : f.affine)
    if (!std::isfinite(a)) return "non-finite affine flow";
  for (double c : f.covariance)
    if (!std::isfinite(c)) return "non-finite covariance";
  const double dt = f.t - f.t_prev;
  if (!(dt >= min_interval && dt <= max_interval))
    return "interval " + std::to_string(dt) + " s outside [" + std::to_string(min_interval) + ", " +
           std::to_string(max_interval) + "] s";
  // No camera has 1e4 px; beyond, the numbers are garbage, not motion.
  constexpr double kMaxDisplacement = 1e4, kMaxGradient = 1e3;
  if (std::abs(f.affine[0]) > kMaxDisplacement || std::abs(f.affine[1]) > kMaxDisplacement)
    return "displacement beyond 1e4 px";
  for (int i = 2; i < 6; ++i)
    if (std::abs(f.affine[i]) > kMaxGradient) return "flow gradient beyond 1e3 per frame";
  const Mat2 C = f.displacementCovariance();
  if (std::abs(C(0, 1) - C(1, 0)) > 1e-9 * (1 + C.cwiseAbs().maxCoeff()) || C(0, 0) <= 0 || C(1, 1) <= 0 ||
      C.determinant() <= 0 || C.trace() > kMaxDisplacement * kMaxDisplacement)
    return "displacement covariance not symmetric positive definite, or beyond (1e4 px)^2";
  return "";
}

FlowPrediction predictFlow(const RayGeometry& g0, const Eigen::Isometry3d& T_c1_c0, const Vec3& e, double dt,
                           const ImagingCamera& cam) {
  const Vec3 X0 = g0.point();
  const Vec3 X1 = T_c1_c0 * X0 + e * dt;
  FlowPrediction p;
  p.displacement = cam.project(X1) - cam.project(X0);
  const Mat23 J1 = cam.projectJacobian(X1);
  p.H = J1 * dt;
  // X0 moves along its own ray with the depth: pi(X0) stays, pi(X1) moves
  // by J1 R10 r.
  const Vec2 dd = J1 * (T_c1_c0.linear() * g0.ray);
  p.R_geometry = g0.covariance(0, 0) * dd * dd.transpose();
  return p;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
