// The gyro motion model (motion_model.hpp, docs/DESIGN.md "Gyro prediction"):
// the camera state [dp, dtheta, dv, dw] of the constant-velocity model and the
// gyro's bias dbg (IMU axes), 15 rows. Each sample, less the bias and rotated
// into the camera frame with the extrinsic's rotation (the lever arm does not
// change an angular rate), replaces w for the step:
//   w <- R_bc^T (w_m - b_g),  so  dw' = -R_bc^T dbg + n_g.
// A real MEMS gyro's turn-on bias reaches 0.1 rad/s; without the bias state
// the filter would take it for a rotation the frames keep contradicting.
// The bias starts at zero with initial_sigma_gyro_bias and random-walks with
// gyro_random_walk; the frames' rotations determine it.
#include "motion_models.hpp"

namespace hapi_eskf {
namespace {

class GyroMotionModel final : public CameraStateMotionModel {
 public:
  using CameraStateMotionModel::CameraStateMotionModel;

  MotionModelKind kind() const override { return MotionModelKind::kGyro; }
  int poseDim() const override { return kGyroDim; }
  bool usesImu() const override { return true; }

  PoseMat initialCovariance() const override {
    PoseMat C = cameraStateCovariance();
    C.diagonal().segment<3>(kIdxGyroBias).setConstant(s_.initial_sigma_gyro_bias * s_.initial_sigma_gyro_bias);
    return C;
  }

  // With a sample: gyroStep (backend/pose_kinematics.hpp) with the
  // bias-corrected rate, F_cv's w columns carrying -R_bc^T into the bias
  // columns; the bias random-walks. Without one: the constant-velocity step.
  void step(const NominalState& x, double dt, const ImuSample* imu, NominalState* next, PoseMat* F,
            PoseMat* Q) const override {
    *next = x;
    *F = PoseMat::Identity(kGyroDim, kGyroDim);
    *Q = PoseMat::Zero(kGyroDim, kGyroDim);
    PoseState y;
    if (imu != nullptr) {
      const Mat3 Rcb = extrinsic_.R_imu_cam.transpose();
      const Vec3 rate = Rcb * (imu->gyro - x.b_g);
      Mat12 F12, Q12;
      // The step's noise is isotropic: the largest axis' density.
      gyroStep(toPose(x), rate, imuNoiseDensities(x, s_).gyro.maxCoeff(), dt, s_, &y, &F12, &Q12);
      PoseState xg = toPose(x);
      xg.w = rate;
      F->topLeftCorner<12, 12>() = F12;
      F->block<12, 3>(0, kIdxGyroBias) = -predictJacobian(xg, dt, s_).block<12, 3>(0, kIdxW) * Rcb;
      Q->topLeftCorner<12, 12>() = Q12;
    } else {
      y = predictPose(toPose(x), dt, s_);
      F->topLeftCorner<12, 12>() = predictJacobian(toPose(x), dt, s_);
      Q->topLeftCorner<12, 12>() = processNoise(dt, s_);
    }
    Q->block<3, 3>(kIdxGyroBias, kIdxGyroBias) = Mat3::Identity() * (s_.gyro_random_walk * s_.gyro_random_walk * dt);
    fromPose(y, next);
  }

  void inject(NominalState* x, const Eigen::Ref<const Eigen::VectorXd>& dx) const override {
    injectCameraState(x, dx);
    x->b_g += dx.segment<3>(kIdxGyroBias);
  }

  Eigen::VectorXd errorBetween(const NominalState& x, const NominalState& x_hat) const override {
    Eigen::VectorXd e = cameraStateError(x, x_hat);
    e.segment<3>(kIdxGyroBias) = x.b_g - x_hat.b_g;
    return e;
  }
};

}  // namespace

std::unique_ptr<MotionModel> makeGyroMotionModel(const EskfSettings& s, const CameraExtrinsic& e) {
  return std::make_unique<GyroMotionModel>(s, e);
}

}  // namespace hapi_eskf
