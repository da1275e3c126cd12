// The constant-velocity motion model (motion_model.hpp, docs/DESIGN.md
// "Predict"): the thesis's 12-row pose block [dp, dtheta, dv, dw] of the left
// camera, stepped by the functions of backend/pose_kinematics.hpp.
#include "motion_models.hpp"

namespace hapi_eskf {
namespace {

class ConstantVelocityMotionModel final : public CameraStateMotionModel {
 public:
  using CameraStateMotionModel::CameraStateMotionModel;

  MotionModelKind kind() const override { return MotionModelKind::kConstantVelocity; }
  int poseDim() const override { return kCameraMotionDim; }
  bool usesImu() const override { return false; }
  PoseMat initialCovariance() const override { return cameraStateCovariance(); }

  void step(const NominalState& x, double dt, const ImuSample*, NominalState* next, PoseMat* F,
            PoseMat* Q) const override {
    *next = x;
    fromPose(predictPose(toPose(x), dt, s_), next);
    *F = predictJacobian(toPose(x), dt, s_);
    *Q = processNoise(dt, s_);
  }

  void inject(NominalState* x, const Eigen::Ref<const Eigen::VectorXd>& dx) const override {
    injectCameraState(x, dx);
  }
  Eigen::VectorXd errorBetween(const NominalState& x, const NominalState& x_hat) const override {
    return cameraStateError(x, x_hat);
  }
};

}  // namespace

std::unique_ptr<MotionModel> makeConstantVelocityMotionModel(const EskfSettings& s, const CameraExtrinsic& e) {
  return std::make_unique<ConstantVelocityMotionModel>(s, e);
}

}  // namespace hapi_eskf
