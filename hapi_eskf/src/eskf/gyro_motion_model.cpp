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
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "motion_models.hpp"
#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {
namespace {

class GyroMotionModel final : public MotionModel {
 public:
  GyroMotionModel(const EskfSettings& s, const CameraExtrinsic& e) : MotionModel(e), s_(s) {}

  MotionModelKind kind() const override { return MotionModelKind::kGyro; }
  int poseDim() const override { return kGyroDim; }
  bool usesImu() const override { return true; }

  NominalState fromCamera(const PoseState& camera) const override {
    NominalState x;
    fromPose(camera, &x);
    return x;
  }

  PoseMat initialCovariance() const override {
    PoseMat C = cameraStateInitialCovariance(s_, kGyroDim);
    C.diagonal().segment<3>(kIdxGyroBias).setConstant(s_.initial_sigma_gyro_bias * s_.initial_sigma_gyro_bias);
    return C;
  }

  PoseState camera(const NominalState& x) const override { return toPose(x); }
  Eigen::Matrix<double, 12, Eigen::Dynamic> cameraStateJacobian(const NominalState&) const override {
    return Eigen::Matrix<double, 12, Eigen::Dynamic>::Identity(12, kGyroDim);
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
      gyroStep(toPose(x), rate, s_.gyroProcessNoiseDensity(), dt, s_, &y, &F12, &Q12);
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
    PoseState p = toPose(*x);
    injectPose(&p, dx.head<12>());
    fromPose(p, x);
    x->b_g += dx.segment<3>(kIdxGyroBias);
  }

  Eigen::VectorXd errorBetween(const NominalState& x, const NominalState& x_hat) const override {
    Eigen::VectorXd e(kGyroDim);
    e.segment<3>(kIdxP) = x.p - x_hat.p;
    e.segment<3>(kIdxTheta) = logSO3((x_hat.q.conjugate() * x.q).toRotationMatrix());
    e.segment<3>(kIdxV) = x.v - x_hat.v;
    e.segment<3>(kIdxW) = x.w - x_hat.w;
    e.segment<3>(kIdxGyroBias) = x.b_g - x_hat.b_g;
    return e;
  }

 private:
  EskfSettings s_;
};

}  // namespace

std::unique_ptr<MotionModel> makeGyroMotionModel(const EskfSettings& s, const CameraExtrinsic& e) {
  return std::make_unique<GyroMotionModel>(s, e);
}

}  // namespace hapi_eskf
