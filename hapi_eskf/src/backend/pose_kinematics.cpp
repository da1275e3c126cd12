// Constant-velocity pose kinematics and their error-state Jacobians (docs/DESIGN.md
// "State and error state"), shared by every back end: the ES-EKF's camera motion
// models, Graph SLAM's and FastSLAM's pose prediction, and the covariance
// storages' pose-block step. Error convention:
//   p = p^ + dp, R = R^ Exp(dtheta), v = v^ + dv, w = w^ + dw.
// Each Jacobian is derived to first order next to the code and checked
// numerically in test/test_jacobians.cpp.
#include "hapi_eskf/backend/pose_kinematics.hpp"

#include "hapi_eskf/so3.hpp"

#include <cmath>

namespace hapi_eskf {
namespace {

// Damping factors are given per second; a step of dt applies Gamma^dt.
double dampingFactor(double per_second, double dt) { return std::pow(per_second, dt); }

}  // namespace

PoseState predictPose(const PoseState& x, double dt, const MotionSettings& s) {
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
Mat12 predictJacobian(const PoseState& x, double dt, const MotionSettings& s) {
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
void gyroStep(const PoseState& x, const Vec3& gyro_camera, double sigma_gyro, double dt, const MotionSettings& s,
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

Mat12 processNoise(double dt, const MotionSettings& s) {
  Mat12 Q = Mat12::Zero();
  Q.block<3, 3>(kIdxV, kIdxV).diagonal().setConstant(s.sigma_acceleration * s.sigma_acceleration * dt);
  Q.block<3, 3>(kIdxW, kIdxW).diagonal().setConstant(s.sigma_angular_acceleration * s.sigma_angular_acceleration *
                                                      dt);
  return Q;
}

void injectPose(PoseState* x, const Eigen::Ref<const Eigen::VectorXd>& dx12) {
  x->p += dx12.segment<3>(kIdxP);
  x->q = (x->q * quatExp(dx12.segment<3>(kIdxTheta))).normalized();
  x->v += dx12.segment<3>(kIdxV);
  x->w += dx12.segment<3>(kIdxW);
}

}  // namespace hapi_eskf
