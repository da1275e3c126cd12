// Models and Jacobians of docs/DESIGN.md "State and error state". Error convention:
//   p = p^ + dp, R = R^ Exp(dtheta), v = v^ + dv, w = w^ + dw, m = m^ + dm.
// Each Jacobian below is derived to first order in that convention; the
// derivations are repeated next to the code and checked numerically in
// test/test_jacobians.cpp.
#include "hapi_eskf/jacobians.hpp"

#include "hapi_eskf/so3.hpp"

#include <cmath>

namespace hapi_eskf {
namespace {

// Damping factors are given per second; a step of dt applies Gamma^dt.
double dampingFactor(double per_second, double dt) { return std::pow(per_second, dt); }

}  // namespace

PoseState predictPose(const PoseState& x, double dt, const EskfSettings& s) {
  PoseState y;
  const Mat3 R = x.q.toRotationMatrix();
  y.p = x.p + R * x.v * dt;
  y.q = (x.q * quatExp(x.w * dt)).normalized();
  y.v = dampingFactor(s.velocity_damping, dt) * x.v;
  y.w = dampingFactor(s.angular_velocity_damping, dt) * x.w;
  return y;
}

// dp'     = dp + R^ Exp(dth)(v^+dv) dt - R^ v^ dt  ~ dp - R^[v^]x dt dth + R^ dt dv
// Exp(dth') = Exp(-w^dt) Exp(dth) Exp(w^dt + dw dt)
//          ~ Exp(Exp(w^dt)^T dth) Exp(J_r(w^dt) dw dt)
//   => dth' = Exp(w^dt)^T dth + J_r(w^ dt) dt dw
// dv' = Gamma^dt dv, dw' = Lambda^dt dw.
Mat12 predictJacobian(const PoseState& x, double dt, const EskfSettings& s) {
  const Mat3 R = x.q.toRotationMatrix();
  const Vec3 phi = x.w * dt;
  Mat12 F = Mat12::Identity();
  F.block<3, 3>(kIdxP, kIdxTheta) = -R * skew(x.v) * dt;
  F.block<3, 3>(kIdxP, kIdxV) = R * dt;
  F.block<3, 3>(kIdxTheta, kIdxTheta) = expSO3(phi).transpose();
  F.block<3, 3>(kIdxTheta, kIdxW) = rightJacobianSO3(phi) * dt;
  F.block<3, 3>(kIdxV, kIdxV) = dampingFactor(s.velocity_damping, dt) * Mat3::Identity();
  F.block<3, 3>(kIdxW, kIdxW) = dampingFactor(s.angular_velocity_damping, dt) * Mat3::Identity();
  return F;
}

// Random walks: v and w receive white acceleration noise of density sigma,
// i.e. variance sigma^2 dt per step. Its effect on p and theta enters through
// F at the following steps (first order in dt).
void gyroStep(const PoseState& x, const Vec3& gyro_camera, double sigma_gyro, double dt, const EskfSettings& s,
              PoseState* next, Mat12* F, Mat12* Q) {
  PoseState xg = x;
  xg.w = gyro_camera;
  Mat12 F_rep = Mat12::Identity();
  F_rep.block<3, 3>(kIdxW, kIdxW).setZero();
  Mat12 Q_rep = Mat12::Zero();
  Q_rep.block<3, 3>(kIdxW, kIdxW).diagonal().setConstant(sigma_gyro * sigma_gyro / dt);
  const Mat12 F_cv = predictJacobian(xg, dt, s);
  *F = F_cv * F_rep;
  *Q = F_cv * Q_rep * F_cv.transpose() + processNoise(dt, s);
  *next = predictPose(xg, dt, s);
}

PoseMat predictPoseCovariance(const PoseMat& C, const PoseMat& F, const PoseMat& Q) {
  const PoseMat Cn = F * C * F.transpose() + Q;
  return 0.5 * (Cn + Cn.transpose());
}

Mat6 poseRandomWalkNoise(double dt, double sigma_acceleration, double sigma_angular_acceleration) {
  Mat6 Q = Mat6::Zero();
  const double k = dt * dt * dt / 3.0;
  Q.block<3, 3>(0, 0) = sigma_acceleration * sigma_acceleration * k * Mat3::Identity();
  Q.block<3, 3>(3, 3) = sigma_angular_acceleration * sigma_angular_acceleration * k * Mat3::Identity();
  return Q;
}

Mat12 processNoise(double dt, const EskfSettings& s) {
  Mat12 Q = Mat12::Zero();
  Q.block<3, 3>(kIdxV, kIdxV).diagonal().setConstant(s.sigma_acceleration * s.sigma_acceleration * dt);
  Q.block<3, 3>(kIdxW, kIdxW).diagonal().setConstant(s.sigma_angular_acceleration * s.sigma_angular_acceleration *
                                                      dt);
  return Q;
}

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

void injectPose(PoseState* x, const Eigen::Ref<const Eigen::VectorXd>& dx12) {
  x->p += dx12.segment<3>(kIdxP);
  x->q = (x->q * quatExp(dx12.segment<3>(kIdxTheta))).normalized();
  x->v += dx12.segment<3>(kIdxV);
  x->w += dx12.segment<3>(kIdxW);
}

}  // namespace hapi_eskf
