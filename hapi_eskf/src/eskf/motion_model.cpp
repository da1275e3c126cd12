// Model choice and the IMU clock rule of motion_model.hpp.
#include "hapi_eskf/eskf/motion_model.hpp"

#include "motion_models.hpp"

namespace hapi_eskf {

std::unique_ptr<MotionModel> makeMotionModel(const EskfSettings& s, const CameraExtrinsic& extrinsic) {
  switch (s.motion_model) {
    case MotionModelKind::kInertial:
      return makeInertialMotionModel(s, extrinsic);
    case MotionModelKind::kGyro:
      return makeGyroMotionModel(s, extrinsic);
    case MotionModelKind::kConstantVelocity:
      break;
  }
  return makeConstantVelocityMotionModel(s, extrinsic);
}

namespace {
// The rows after the inertial model's 18 (calibration, scene motion) are the
// ES-EKF's; the SEIF's information-form motion update and the other back
// ends (no inertial pose block) do not estimate them.
bool hasExtraInertialRows(const EskfSettings& s) {
  return s.motion_model == MotionModelKind::kInertial && s.backend_algorithm == BackendAlgorithm::kEskf;
}
}  // namespace

CalibrationLayout calibrationLayout(const EskfSettings& s) {
  CalibrationLayout l;
  if (!hasExtraInertialRows(s)) return l;
  int row = kInertialDim;
  if (s.calib_cam_extrinsics) {
    l.extrinsic = row;
    row += kCalibExtrinsicDim;
  }
  if (s.calib_cam_timeoffset) l.time_offset = row;
  return l;
}

SceneMotionLayout sceneMotionLayout(const EskfSettings& s) {
  SceneMotionLayout l;
  if (!s.scene_motion || !hasExtraInertialRows(s)) return l;
  l.row = kInertialDim + calibrationLayout(s).dim();
  return l;
}

int poseDim(const EskfSettings& s) {
  switch (s.motion_model) {
    case MotionModelKind::kInertial:
      return kInertialDim + calibrationLayout(s).dim() + sceneMotionLayout(s).dim();
    case MotionModelKind::kGyro:
      return kGyroDim;
    case MotionModelKind::kConstantVelocity:
      break;
  }
  return kCameraMotionDim;
}

Mat12 cameraCovariance(const MotionModel& model, const NominalState& x, const PoseMat& C) {
  const Eigen::Matrix<double, 12, Eigen::Dynamic> T = model.cameraStateJacobian(x);
  const Mat12 Cc = T * C * T.transpose();
  return 0.5 * (Cc + Cc.transpose());
}

Mat6 poseCovarianceInWorldAxes(const PoseState& camera, const Mat12& camera_covariance) {
  Mat6 J = Mat6::Identity();
  J.block<3, 3>(3, 3) = camera.q.toRotationMatrix();
  return J * camera_covariance.topLeftCorner<6, 6>() * J.transpose();
}

ImuNoiseDensity imuNoiseDensities(const NominalState& x, const EskfSettings& s) {
  ImuNoiseDensity n;
  n.gyro = x.imu_noise.gyro.cwiseMax(s.gyro_noise_density) * s.gyro_noise_inflation;
  n.accel = x.imu_noise.accel.cwiseMax(s.accel_noise_density);
  return n;
}

ImuSample imuSampleOnCameraClock(double imu_stamp, const Vec3& gyro, const Vec3& accel, const EskfSettings& s) {
  ImuSample out;
  out.stamp = imu_stamp - s.imu_time_offset;
  out.gyro = gyro;
  out.accel = accel;
  return out;
}

}  // namespace hapi_eskf
