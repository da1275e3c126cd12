// The concrete motion models (motion_model.hpp), one source file each;
// makeMotionModel (motion_model.cpp) picks one from the settings.
#pragma once

#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {

std::unique_ptr<MotionModel> makeConstantVelocityMotionModel(const EskfSettings& s, const CameraExtrinsic& e);
std::unique_ptr<MotionModel> makeGyroMotionModel(const EskfSettings& s, const CameraExtrinsic& e);
std::unique_ptr<MotionModel> makeInertialMotionModel(const EskfSettings& s, const CameraExtrinsic& e);

// The camera state [p, q, v, w] of the camera-state models (constant_velocity
// and gyro) as the kinematics of backend/pose_kinematics.hpp take it.
inline PoseState toPose(const NominalState& x) {
  PoseState p;
  p.p = x.p;
  p.q = x.q;
  p.v = x.v;
  p.w = x.w;
  return p;
}

inline void fromPose(const PoseState& p, NominalState* x) {
  x->p = p.p;
  x->q = p.q;
  x->v = p.v;
  x->w = p.w;
}

// The camera-state models (constant_velocity, gyro): the first 12 rows are
// the camera's [dp, dtheta, dv, dw] (backend/pose_kinematics.hpp), v in the
// camera frame; a model appends its own rows after them.
class CameraStateMotionModel : public MotionModel {
 public:
  CameraStateMotionModel(const EskfSettings& s, const CameraExtrinsic& e) : MotionModel(e), s_(s) {}

  NominalState fromCamera(const PoseState& camera) const override {
    NominalState x;
    fromPose(camera, &x);
    return x;
  }
  PoseState camera(const NominalState& x) const override { return toPose(x); }
  Eigen::Matrix<double, 12, Eigen::Dynamic> cameraStateJacobian(const NominalState&) const override {
    return Eigen::Matrix<double, 12, Eigen::Dynamic>::Identity(12, poseDim());
  }
  void moveCameraTo(NominalState* x, const Vec3& p, const Eigen::Quaterniond& q) const override {
    x->p = p;
    x->q = q.normalized();
  }
  void stop(NominalState* x) const override {
    x->v.setZero();
    x->w.setZero();
  }
  void correctVelocity(NominalState* x, const Vec3& dp_world, double dt, bool) const override {
    x->v += x->q.conjugate() * dp_world / dt;
  }

 protected:
  // The first camera state's uncertainty (its first 12 rows; the rest zero).
  PoseMat cameraStateCovariance() const {
    PoseMat C = PoseMat::Zero(poseDim(), poseDim());
    C.diagonal().segment<3>(kIdxP).setConstant(s_.initial_sigma_position * s_.initial_sigma_position);
    C.diagonal().segment<3>(kIdxTheta).setConstant(s_.initial_sigma_orientation * s_.initial_sigma_orientation);
    C.diagonal().segment<3>(kIdxV).setConstant(s_.initial_sigma_velocity * s_.initial_sigma_velocity);
    C.diagonal().segment<3>(kIdxW).setConstant(s_.initial_sigma_angular_velocity * s_.initial_sigma_angular_velocity);
    return C;
  }
  // The camera rows of inject and errorBetween.
  static void injectCameraState(NominalState* x, const Eigen::Ref<const Eigen::VectorXd>& dx) {
    PoseState p = toPose(*x);
    injectPose(&p, dx.head<12>());
    fromPose(p, x);
  }
  Eigen::VectorXd cameraStateError(const NominalState& x, const NominalState& x_hat) const {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(poseDim());
    e.segment<3>(kIdxP) = x.p - x_hat.p;
    e.segment<3>(kIdxTheta) = logSO3((x_hat.q.conjugate() * x.q).toRotationMatrix());
    e.segment<3>(kIdxV) = x.v - x_hat.v;
    e.segment<3>(kIdxW) = x.w - x_hat.w;
    return e;
  }

  EskfSettings s_;
};

}  // namespace hapi_eskf
