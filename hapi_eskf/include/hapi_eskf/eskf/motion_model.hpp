// The filter's motion models (docs/DESIGN.md "Motion models"): what the pose
// block of the state is, how it is predicted (with or without an IMU sample),
// the error-state transition F and process noise Q of each step, the camera
// pose a measurement sees, and how a correction is injected.
//
// A model is a stateless strategy over a NominalState value: the filter, its
// IMU-rate copy (the nodelet's PosePropagator) and the tools hold a state and
// run the same model on it, so they cannot step differently. Three models
// (settings motion_model):
//  * constant_velocity: the thesis's camera state [p, theta, v, w] (12),
//    v and w in the camera frame, random walks on v and w;
//  * gyro: the same state, w replaced by each gyro sample for the step;
//  * inertial: the IMU body state [p, theta, v, b_g, b_a, g] (18), v in the
//    world frame, propagated with gyro and accelerometer (the standard
//    quaternion ES-EKF); the camera pose follows through the camera-IMU
//    extrinsic; with online calibration (settings calib_cam_*) the
//    extrinsic [dtheta_bc, dp_bc] (6) and the time offset [dt_d] (1) follow
//    as states (docs/DESIGN.md "Online calibration"); with scene_motion the
//    surface's velocity and angular rate [u_s, w_s] (6) follow them
//    (docs/DESIGN.md "Scene motion state").
#pragma once

#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <cmath>
#include <memory>

namespace hapi_eskf {

// White-noise densities per IMU axis (gyro [rad/s/sqrt(Hz)], accelerometer
// [m/s^2/sqrt(Hz)]); zero: not measured.
struct ImuNoiseDensity {
  Vec3 gyro = Vec3::Zero(), accel = Vec3::Zero();
};

// The nominal state of the pose block. Which fields are state depends on the
// model (the others are carried along unchanged):
//  camera models: p, q = camera pose in the world; v, w = camera-frame linear
//    and angular velocity;
//  inertial: p, q = IMU body pose in the world; v = world-frame velocity;
//    b_g, b_a = gyro and accelerometer biases; g = gravity in the world;
//    w, f = the last gyro and accelerometer sample as read (body frame, not
//    states: held over a step without a new sample, and w - b_g is the
//    angular rate of the twist output);
//    R_bc, p_bc, t_d = the camera-IMU extrinsic (CameraExtrinsic's) and the
//    time offset (imu_time_offset's meaning) as estimated: states when
//    calibrated (CalibrationLayout), else the configured values, unused;
//    u_s, w_s = the scanned surface's velocity and angular rate in the
//    inertial frame, expressed in the world (surface) frame: states with
//    scene_motion (SceneMotionLayout), else zero.
// IMU models: imu_noise = the IMU's in-situ noise (imu_noise_estimator.hpp),
// not a state: the filter sets it at each frame, so the steps between two
// frames (the filter's and its IMU-rate copy's) assume the same noise.
struct NominalState {
  Vec3 p = Vec3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
  Vec3 b_g = Vec3::Zero(), b_a = Vec3::Zero(), g = Vec3::Zero();
  Vec3 f = Vec3::Zero();
  bool has_imu = false;  // inertial: w and f hold a sample
  Mat3 R_bc = Mat3::Identity();
  Vec3 p_bc = Vec3::Zero();
  double t_d = 0.0;  // [s]
  Vec3 u_s = Vec3::Zero(), w_s = Vec3::Zero();
  ImuNoiseDensity imu_noise;
};

// The white-noise densities an IMU step assumes, per IMU axis: the larger of
// the settings' (the datasheet's) and the in-situ x.imu_noise, the gyro's
// times gyro_noise_inflation (docs/DESIGN.md "In-situ IMU noise").
ImuNoiseDensity imuNoiseDensities(const NominalState& x, const EskfSettings& s);

// Where the online calibration's rows sit in the pose block (-1: not
// estimated). Only the inertial model of the ES-EKF calibrates, after its
// 18 rows; not over the SEIF's storage (its information-form motion update).
struct CalibrationLayout {
  int extrinsic = -1;    // [dtheta_bc, dp_bc]: R_bc = R_bc^ Exp(dtheta_bc), p_bc = p_bc^ + dp_bc
  int time_offset = -1;  // [dt_d]: t_d = t_d^ + dt_d
  bool any() const { return extrinsic >= 0 || time_offset >= 0; }
  int dim() const { return (extrinsic >= 0 ? kCalibExtrinsicDim : 0) + (time_offset >= 0 ? kCalibTimeOffsetDim : 0); }
};
CalibrationLayout calibrationLayout(const EskfSettings& s);

// Where the scanned surface's motion [du_s, dw_s] sits in the pose block (-1:
// not estimated): after the calibration's rows, for the inertial model of
// the ES-EKF with scene_motion.
struct SceneMotionLayout {
  int row = -1;  // u_s = u_s^ + du_s, w_s = w_s^ + dw_s
  bool any() const { return row >= 0; }
  int dim() const { return any() ? kSceneMotionDim : 0; }
};
SceneMotionLayout sceneMotionLayout(const EskfSettings& s);

// The pose-block state an IMU-rate output continues from between frames
// (pose_propagator.hpp, SlamBackend::poseBlockState): back ends whose motion model predicts with the IMU.
struct PoseBlockState {
  CameraExtrinsic extrinsic;
  NominalState x;
  PoseMat C;  // pose block covariance (P x P, P = poseDim(settings))
  double time = 0.0;
  // The velocity in x is measured: a frame updated against the map since
  // the filter last set it to rest as a guess (a start while moving, a
  // prediction after an outage), or a still start measured it zero.
  bool velocity_measured = false;
};

class MotionModel {
 public:
  virtual ~MotionModel() = default;
  virtual MotionModelKind kind() const = 0;
  virtual int poseDim() const = 0;
  virtual bool usesImu() const = 0;
  virtual CalibrationLayout calibration() const { return CalibrationLayout(); }
  virtual SceneMotionLayout sceneMotion() const { return SceneMotionLayout(); }

  // The state at the start, from the camera pose (p, q; v, w as given for
  // the camera models, zero otherwise) and, for the inertial model, the
  // gravity-aligned initialisation (inertial_alignment.hpp) applied by the
  // caller through the returned state's fields.
  virtual NominalState fromCamera(const PoseState& camera) const = 0;
  // The covariance of that state (the initial_sigma_* settings).
  virtual PoseMat initialCovariance() const = 0;
  // initialCovariance() without the [dp, dtheta] and calibration rows and
  // columns: added to C when the motion states (velocities, biases,
  // gravity) turn out inconsistent with vision, so that the next updates
  // estimate them afresh.
  PoseMat motionStatesPrior() const {
    PoseMat C = initialCovariance();
    C.topRows(6).setZero();
    C.leftCols(6).setZero();
    const CalibrationLayout calib = calibration();
    if (calib.any()) {
      const int first = calib.extrinsic >= 0 ? calib.extrinsic : calib.time_offset;
      C.middleRows(first, calib.dim()).setZero();
      C.middleCols(first, calib.dim()).setZero();
    }
    return C;
  }

  // The camera as a measurement sees it: pose in the world, camera-frame
  // linear and angular velocity (relative to the world, i.e. to the
  // surface when its motion is estimated).
  virtual PoseState camera(const NominalState& x) const = 0;
  // d(camera error [dp, dtheta, dv, dw] of camera(x), in the camera models'
  // convention) / d(state error), 12 x P: maps the state covariance to the
  // camera's for the outputs (odometry pose and twist covariance). A
  // calibrated time offset's column is the camera's motion over dt_d: its
  // world velocity and its angular rate (the pose rows; docs/DESIGN.md
  // "Online calibration"), not a change of camera(x).
  virtual Eigen::Matrix<double, 12, Eigen::Dynamic> cameraStateJacobian(const NominalState& x) const = 0;
  // Its [dp, dtheta] block (6 x 6; the camera pose depends on the state pose
  // only): the pose columns of a measurement or new-landmark Jacobian are
  // the camera's times this.
  Mat6 cameraJacobian(const NominalState& x) const { return cameraStateJacobian(x).leftCols<6>().topRows<6>(); }
  // Means moved so that camera(x) has pose (p, q) (relocalisation).
  virtual void moveCameraTo(NominalState* x, const Vec3& p, const Eigen::Quaterniond& q) const = 0;
  // A sample as the filter takes it (stamp on the camera clock with the
  // configured imu_time_offset, imuSampleOnCameraClock) moved to the
  // camera clock of the estimated offset x.t_d when it is calibrated.
  virtual ImuSample onEstimatedClock(const ImuSample& sample, const NominalState& x) const {
    (void)x;
    return sample;
  }
  // Velocity means zeroed (the motion since an outage is unknown).
  virtual void stop(NominalState* x) const = 0;
  // The camera turned out to be dp_world [m, world frame] away from where
  // the prediction over the last dt [s] put it: the velocity mean takes the
  // difference, v += dp_world / dt (IMU and vision disagreement,
  // scene_motion_monitor.hpp: the velocity is what made the prediction miss).
  // scene_moving (the device is held still): a model that estimates the
  // surface's motion gives the difference to the surface instead.
  virtual void correctVelocity(NominalState* x, const Vec3& dp_world, double dt, bool scene_moving) const = 0;

  // One step of length dt > 0, with the sample (a model without IMU ignores
  // it) or without (nullptr: the camera models' constant velocity, the
  // inertial model holds the last sample). next, F (P x P), Q (P x P).
  virtual void step(const NominalState& x, double dt, const ImuSample* imu, NominalState* next, PoseMat* F,
                    PoseMat* Q) const = 0;
  // The transition of the step x -> next re-evaluated at first estimates
  // (docs/DESIGN.md "First-estimate Jacobians"): `lin` is the step's start
  // as first estimated (the predicted state where an update came between,
  // gravity at its first estimate), `next` the propagated mean; F's blocks
  // along the unobservable directions are rewritten from the two so that F
  // maps the null space at `lin` onto the one at `next`. A model whose F
  // does not depend on those states leaves F unchanged (the default).
  virtual void firstEstimateTransition(const NominalState& lin, const NominalState& next, double dt,
                                       PoseMat* F) const {
    (void)lin, (void)next, (void)dt, (void)F;
  }
  // x <- x (+) dx (the pose block of a correction, length P).
  virtual void inject(NominalState* x, const Eigen::Ref<const Eigen::VectorXd>& dx) const = 0;
  // The error e (length P) with x = x_hat (+) e, for the models' state
  // fields only (finite-difference Jacobian tests, NEES).
  virtual Eigen::VectorXd errorBetween(const NominalState& x, const NominalState& x_hat) const = 0;

  const CameraExtrinsic& extrinsic() const { return extrinsic_; }

 protected:
  explicit MotionModel(const CameraExtrinsic& e) : extrinsic_(e) {}
  CameraExtrinsic extrinsic_;
};

// The model of s.motion_model with the camera-IMU extrinsic (ignored by
// constant_velocity; gyro uses its rotation only).
std::unique_ptr<MotionModel> makeMotionModel(const EskfSettings& s, const CameraExtrinsic& extrinsic);
// The pose block of the settings' motion model, calibration rows included.
int poseDim(const EskfSettings& s);

// The camera's covariance [dp, dtheta, dv, dw] (12 x 12) from the pose
// block's C (P x P): T C T^T with T = model.cameraStateJacobian(x),
// symmetrised.
Mat12 cameraCovariance(const MotionModel& model, const NominalState& x, const PoseMat& C);

// The camera pose covariance [dp, dtheta] with the rotation error about the
// world axes (R_wc dtheta) instead of the camera's: the convention of
// nav_msgs/Odometry's pose covariance and of the evaluation tools.
Mat6 poseCovarianceInWorldAxes(const PoseState& camera, const Mat12& camera_covariance);

// An IMU sample as read (stamp on the IMU clock) moved to the camera clock:
// t_cam = t_imu - imu_time_offset (settings.hpp).
ImuSample imuSampleOnCameraClock(double imu_stamp, const Vec3& gyro, const Vec3& accel, const EskfSettings& s);

// One prediction step of `model` on (*x, *time) to `stamp`, transactional:
// argument checks, then apply(F, Q) propagates the caller's covariance and
// returns its Status; only on kOk are *x and *time committed. kNonFinite,
// kInvalidArgument (stamp before *time); stamp == *time is a no-op (kOk).
// Eskf (covariance in the backend) and the nodelet's PosePropagator (its own
// pose covariance) both run this one path.
// `lin` (optional): the step's start as first estimated; F is then
// MotionModel::firstEstimateTransition's.
template <typename ApplyCovariance>
Status predictStep(const MotionModel& model, NominalState* x, double* time, double stamp, const ImuSample* imu,
                   ApplyCovariance&& apply, const NominalState* lin = nullptr) {
  if (!std::isfinite(stamp)) return Status::kNonFinite;
  if (imu != nullptr && (!imu->gyro.allFinite() || !imu->accel.allFinite())) return Status::kNonFinite;
  if (stamp < *time) return Status::kInvalidArgument;
  const double dt = stamp - *time;
  if (dt == 0.0) return Status::kOk;
  NominalState next;
  PoseMat F, Q;
  model.step(*x, dt, imu, &next, &F, &Q);
  if (lin != nullptr) model.firstEstimateTransition(*lin, next, dt, &F);
  const Status st = apply(F, Q);
  if (st != Status::kOk) return st;
  *x = next;
  *time = stamp;
  return Status::kOk;
}

}  // namespace hapi_eskf
