// The concrete motion models (motion_model.hpp), one source file each;
// makeMotionModel (motion_model.cpp) picks one from the settings.
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"

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

// The first camera state's uncertainty (its first 12 rows; the rest zero).
inline PoseMat cameraStateInitialCovariance(const EskfSettings& s, int dim) {
  PoseMat C = PoseMat::Zero(dim, dim);
  C.diagonal().segment<3>(kIdxP).setConstant(s.initial_sigma_position * s.initial_sigma_position);
  C.diagonal().segment<3>(kIdxTheta).setConstant(s.initial_sigma_orientation * s.initial_sigma_orientation);
  C.diagonal().segment<3>(kIdxV).setConstant(s.initial_sigma_velocity * s.initial_sigma_velocity);
  C.diagonal().segment<3>(kIdxW).setConstant(s.initial_sigma_angular_velocity * s.initial_sigma_angular_velocity);
  return C;
}

}  // namespace hapi_eskf
