// Pose-only robust Gauss-Newton (pose_tracker.hpp).
#include "hapi_eskf/graph/pose_tracker.hpp"

#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/so3.hpp"

#include <Eigen/Cholesky>

#include <cmath>

namespace hapi_eskf {
namespace graph {

double robustWeight(const GraphSettings& settings, double s) {
  const double a2 = settings.robust_scale * settings.robust_scale;
  switch (settings.robust_loss) {
    case RobustLoss::kHuber: return s <= a2 ? 1.0 : std::sqrt(a2 / s);
    case RobustLoss::kCauchy: return 1.0 / (1.0 + s / a2);
    case RobustLoss::kNone: break;
  }
  return 1.0;
}

bool trackPose(const std::vector<TrackedPoint>& points, const PoseState& predicted, const GraphSettings& settings,
               PoseState* pose, Mat6* C) {
  if (points.size() < 3) return false;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  PoseState x = predicted;
  Mat6 A = Mat6::Zero();
  for (int it = 0; it < settings.tracking_iterations; ++it) {
    A.setZero();
    Vec6 g = Vec6::Zero();
    for (const TrackedPoint& t : points) {
      Mat36 H;
      Mat3 Hm;
      measurementJacobian(x, t.m, &H, &Hm);
      const Mat3 S = t.Cz + Hm * t.Cm * Hm.transpose();
      const Eigen::LLT<Mat3> llt(S);
      if (llt.info() != Eigen::Success) continue;
      const Vec3 e = t.z - measure(x, t.m);
      const Vec3 r = llt.matrixL().solve(e);
      const double w = robustWeight(settings, r.squaredNorm());
      const Mat36 Hw = llt.matrixL().solve(H);
      A += w * Hw.transpose() * Hw;
      g += w * Hw.transpose() * r;
    }
    const Eigen::LDLT<Mat6> ldlt(A);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return false;
    const Vec6 d = ldlt.solve(g);  // e ~ H d: minimises |r - Hw d|^2
    if (!d.allFinite()) return false;
    x.p += d.head<3>();
    x.q = (x.q * quatExp(d.tail<3>())).normalized();
    if (d.norm() < 1e-9) break;
  }
  const Eigen::LDLT<Mat6> ldlt(A);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return false;
  Mat6 P = ldlt.solve(Mat6::Identity());
  P = 0.5 * (P + P.transpose());
  if (!P.allFinite()) return false;
  x.v = predicted.v;
  x.w = predicted.w;
  *pose = x;
  *C = P;
  return true;
}

}  // namespace graph
}  // namespace hapi_eskf
