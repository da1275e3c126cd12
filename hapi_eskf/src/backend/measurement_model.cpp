// The stereo 3D measurement model of docs/DESIGN.md "State and error state",
// shared by the association and every back end: a landmark seen from the
// camera, a new landmark placed from a measurement, their Jacobians and the
// re-detection covariance. Error convention: p = p^ + dp, R = R^ Exp(dtheta),
// m = m^ + dm. Checked numerically in test/test_jacobians.cpp.
#include "hapi_eskf/backend/measurement_model.hpp"

#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {

Vec3 measure(const PoseState& x, const Vec3& m) { return x.q.toRotationMatrix().transpose() * (m - x.p); }

// h = Exp(-dth) R^T (m - p - dp) ~ h^ - [dth]x h^ - R^T dp = h^ + [h^]x dth - R^T dp;
// dh/ddm = R^T.
void measurementJacobian(const PoseState& x, const Vec3& m, Mat36* H_pose, Mat3* H_landmark) {
  const Mat3 Rt = x.q.toRotationMatrix().transpose();
  const Vec3 h = Rt * (m - x.p);
  H_pose->block<3, 3>(0, 0) = -Rt;
  H_pose->block<3, 3>(0, 3) = skew(h);
  *H_landmark = Rt;
}

Mat3 redetectionCovariance(const Vec3& z, double angular_sigma) {
  const double s = angular_sigma, d2 = z.squaredNorm();
  if (!(s > 0.0) || !(d2 > 0.0)) return Mat3::Zero();
  // (s |z|)^2 (I - z z^T / |z|^2) = s^2 (|z|^2 I - z z^T)
  return s * s * (d2 * Mat3::Identity() - z * z.transpose());
}

Vec3 initLandmark(const PoseState& x, const Vec3& z) { return x.p + x.q.toRotationMatrix() * z; }

// m = p + R^ Exp(dth)(z + dz) ~ m^ + dp - R^[z]x dth + R^ dz.
void newLandmarkJacobian(const PoseState& x, const Vec3& z, Mat36* G_pose, Mat3* G_z) {
  const Mat3 R = x.q.toRotationMatrix();
  G_pose->block<3, 3>(0, 0) = Mat3::Identity();
  G_pose->block<3, 3>(0, 3) = -R * skew(z);
  *G_z = R;
}

}  // namespace hapi_eskf
