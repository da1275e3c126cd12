// The constant-velocity motion model (motion_model.hpp, docs/DESIGN.md
// "Predict"): the thesis's 12-row pose block [dp, dtheta, dv, dw] of the left
// camera, stepped by the functions of backend/pose_kinematics.hpp.
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "motion_models.hpp"
#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {
namespace {

class ConstantVelocityMotionModel final : public MotionModel {
 public:
  ConstantVelocityMotionModel(const EskfSettings& s, const CameraExtrinsic& e) : MotionModel(e), s_(s) {}

  MotionModelKind kind() const override { return MotionModelKind::kConstantVelocity; }
  int poseDim() const override { return kCameraMotionDim; }
  bool usesImu() const override { return false; }

  NominalState fromCamera(const PoseState& camera) const override {
    NominalState x;
    fromPose(camera, &x);
    return x;
  }

  PoseMat initialCovariance() const override {
    return cameraStateInitialCovariance(s_, kCameraMotionDim);
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

  void step(const NominalState& x, double dt, const ImuSample*, NominalState* next, PoseMat* F,
            PoseMat* Q) const override {
    *next = x;
    fromPose(predictPose(toPose(x), dt, s_), next);
    *F = predictJacobian(toPose(x), dt, s_);
    *Q = processNoise(dt, s_);
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
};

}  // namespace

std::unique_ptr<MotionModel> makeConstantVelocityMotionModel(const EskfSettings& s, const CameraExtrinsic& e) {
  return std::make_unique<ConstantVelocityMotionModel>(s, e);
}

}  // namespace hapi_eskf
