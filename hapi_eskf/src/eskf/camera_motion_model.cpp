// The camera-state motion models, constant_velocity and gyro (motion_model.hpp,
// docs/DESIGN.md "Predict" and "Gyro prediction"): the thesis's 12-row pose
// block [dp, dtheta, dv, dw] of the left camera, stepped by the functions of
// backend/pose_kinematics.hpp. The gyro model rotates each sample into the camera frame
// with the extrinsic's rotation (the lever arm does not change an angular
// rate) and lets it replace w for the step.
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "motion_models.hpp"
#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {
namespace {

PoseState toPose(const NominalState& x) {
  PoseState p;
  p.p = x.p;
  p.q = x.q;
  p.v = x.v;
  p.w = x.w;
  return p;
}

void fromPose(const PoseState& p, NominalState* x) {
  x->p = p.p;
  x->q = p.q;
  x->v = p.v;
  x->w = p.w;
}

class CameraMotionModel final : public MotionModel {
 public:
  CameraMotionModel(const EskfSettings& s, const CameraExtrinsic& e, bool use_gyro)
      : MotionModel(e), s_(s), use_gyro_(use_gyro) {}

  MotionModelKind kind() const override {
    return use_gyro_ ? MotionModelKind::kGyro : MotionModelKind::kConstantVelocity;
  }
  int poseDim() const override { return kCameraMotionDim; }
  bool usesImu() const override { return use_gyro_; }

  NominalState fromCamera(const PoseState& camera) const override {
    NominalState x;
    fromPose(camera, &x);
    return x;
  }

  PoseMat initialCovariance() const override {
    PoseMat C = PoseMat::Zero(kCameraMotionDim, kCameraMotionDim);
    C.diagonal().segment<3>(kIdxP).setConstant(s_.initial_sigma_position * s_.initial_sigma_position);
    C.diagonal().segment<3>(kIdxTheta).setConstant(s_.initial_sigma_orientation * s_.initial_sigma_orientation);
    C.diagonal().segment<3>(kIdxV).setConstant(s_.initial_sigma_velocity * s_.initial_sigma_velocity);
    C.diagonal().segment<3>(kIdxW).setConstant(s_.initial_sigma_angular_velocity * s_.initial_sigma_angular_velocity);
    return C;
  }

  PoseState camera(const NominalState& x) const override { return toPose(x); }
  Eigen::Matrix<double, 12, Eigen::Dynamic> cameraStateJacobian(const NominalState&) const override {
    return Eigen::Matrix<double, 12, Eigen::Dynamic>::Identity(12, kCameraMotionDim);
  }

  void moveCameraTo(NominalState* x, const Vec3& p, const Eigen::Quaterniond& q) const override {
    x->p = p;
    x->q = q.normalized();
  }
  void stop(NominalState* x) const override {
    x->v.setZero();
    x->w.setZero();
  }
  // v is the camera-frame velocity.
  void correctVelocity(NominalState* x, const Vec3& dp_world, double dt) const override {
    x->v += x->q.conjugate() * dp_world / dt;
  }

  void step(const NominalState& x, double dt, const ImuSample* imu, NominalState* next, PoseMat* F,
            PoseMat* Q) const override {
    *next = x;
    PoseState y;
    if (use_gyro_ && imu != nullptr) {
      Mat12 F12, Q12;
      gyroStep(toPose(x), extrinsic_.R_imu_cam.transpose() * imu->gyro, s_.gyroProcessNoiseDensity(), dt, s_, &y, &F12,
               &Q12);
      *F = F12;
      *Q = Q12;
    } else {
      y = predictPose(toPose(x), dt, s_);
      *F = predictJacobian(toPose(x), dt, s_);
      *Q = processNoise(dt, s_);
    }
    fromPose(y, next);
  }

  void inject(NominalState* x, const Eigen::Ref<const Eigen::VectorXd>& dx) const override {
    PoseState p = toPose(*x);
    injectPose(&p, dx);
    fromPose(p, x);
  }

  Eigen::VectorXd errorBetween(const NominalState& x, const NominalState& x_hat) const override {
    Eigen::VectorXd e(kCameraMotionDim);
    e.segment<3>(kIdxP) = x.p - x_hat.p;
    e.segment<3>(kIdxTheta) = logSO3((x_hat.q.conjugate() * x.q).toRotationMatrix());
    e.segment<3>(kIdxV) = x.v - x_hat.v;
    e.segment<3>(kIdxW) = x.w - x_hat.w;
    return e;
  }

 private:
  EskfSettings s_;
  bool use_gyro_;
};

}  // namespace

std::unique_ptr<MotionModel> makeCameraMotionModel(const EskfSettings& s, const CameraExtrinsic& e, bool use_gyro) {
  return std::make_unique<CameraMotionModel>(s, e, use_gyro);
}

}  // namespace hapi_eskf
