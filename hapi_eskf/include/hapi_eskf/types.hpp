// Plain data types of the filter. Frames follow REP-103: the camera frame is
// the left optical frame (x right, y down, z forward); the world frame is
// fixed, and orientation q maps camera to world.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace hapi_eskf {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat36 = Eigen::Matrix<double, 3, 6>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

// Error-state layout (docs/DESIGN.md "State and error state"): a pose block
// of the motion model's size, then 3 rows per landmark. Every model starts
// its block with [dp, dtheta], the only pose columns a measurement touches.
//  * constant_velocity (camera state): [dp, dtheta, dv, dw], 12;
//  * gyro (camera state and the gyro's bias): [dp, dtheta, dv, dw, dbg], 15;
//  * inertial (IMU body state): [dp, dtheta, dv, dbg, dba, dg], 18, then
//    the online calibration's rows when estimated (calibration_block.hpp):
//    the camera-IMU extrinsic [dtheta_bc, dp_bc] (6) and the time offset
//    [dt_d] (1), at most 18 + 7.
//    The scanned surface's motion when estimated (docs/DESIGN.md "Scene
//    motion state"): its velocity and angular rate [du_s, dw_s] (6) after
//    the calibration's, at most 18 + 7 + 6.
// A modelled frame-shared vision error adds 6 spare rows after them
// (frame_error_block.hpp): at most 18 + 7 + 6 + 6.
constexpr int kCameraMotionDim = 12;
constexpr int kGyroDim = 15;
constexpr int kInertialDim = 18;
constexpr int kCalibExtrinsicDim = 6;
constexpr int kCalibTimeOffsetDim = 1;
constexpr int kSceneMotionDim = 6;
constexpr int kFrameErrorDim = 6;
constexpr int kMaxPoseDim = kInertialDim + kCalibExtrinsicDim + kCalibTimeOffsetDim + kSceneMotionDim + kFrameErrorDim;
constexpr int kIdxP = 0, kIdxTheta = 3, kIdxV = 6, kIdxW = 9;    // camera state
constexpr int kIdxBg = 9, kIdxBa = 12, kIdxG = 15;               // inertial state
constexpr int kIdxGyroBias = 12;                                  // gyro model's bias
inline int landmarkRow(int slot, int pose_dim) { return pose_dim + 3 * slot; }
inline int stateDim(int n_landmarks, int pose_dim) { return pose_dim + 3 * n_landmarks; }

// A square block of the pose part (F, Q, the pose covariance): dynamic size
// up to kMaxPoseDim, stored inline (no heap allocation per prediction).
using PoseMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxPoseDim, kMaxPoseDim>;
using PoseVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxPoseDim, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// Nominal pose part of the state.
struct PoseState {
  Vec3 p = Vec3::Zero();                             // camera position in world [m]
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // camera -> world
  Vec3 v = Vec3::Zero();                             // linear velocity, camera frame [m/s]
  Vec3 w = Vec3::Zero();                             // angular velocity, camera frame [rad/s]
};

// One stereo landmark measurement from the front end (hapi_msgs/StereoLandmark).
struct StereoMeasurement {
  Vec3 z = Vec3::Zero();     // position in the camera frame [m]
  Mat3 Cz = Mat3::Identity();  // its covariance [m^2]
  uint32_t frontend_id = 0;  // id within the frame (unique per message)
  float response = 0.f;      // detector strength: higher is better
  std::array<uint8_t, 3> rgb{{0, 0, 0}};
};

// Everything the filter needs from one StereoLandmarks message.
struct StereoFrame {
  double stamp = 0.0;            // [s]
  int descriptor_length = 0;     // bytes per descriptor
  std::vector<uint8_t> descriptors;  // measurements.size() * descriptor_length
  std::vector<StereoMeasurement> measurements;
};

// A landmark of a saved map put back into the pool (Eskf::loadMap): its
// position in the map frame, marginal covariance, observation count and
// descriptor.
struct PriorLandmark {
  Vec3 position = Vec3::Zero();        // [m]
  Mat3 covariance = Mat3::Identity();  // [m^2]
  int times_observed = 1;
  std::vector<uint8_t> descriptor;     // the pool's descriptor length
};

// A landmark of the pool as seen from outside (map publishing, PLY export).
struct LandmarkInfo {
  uint64_t id = 0;           // unique for the lifetime of the filter
  Vec3 position = Vec3::Zero();  // world [m]
  Mat3 covariance = Mat3::Zero();  // marginal [m^2]
  std::array<uint8_t, 3> rgb{{0, 0, 0}};
  int times_observed = 0;
  double last_seen = 0.0;
};

// One IMU sample, in the IMU frame, stamped on the camera clock (the
// settings' imu_time_offset already applied: imuSampleOnCameraClock()).
struct ImuSample {
  double stamp = 0.0;         // [s]
  Vec3 gyro = Vec3::Zero();   // angular velocity [rad/s]
  Vec3 accel = Vec3::Zero();  // specific force [m/s^2] (gravity included, as an accelerometer reads it)
};

// The left camera frame in the IMU frame: X_imu = R_imu_cam X_cam + p_imu_cam.
struct CameraExtrinsic {
  Mat3 R_imu_cam = Mat3::Identity();
  Vec3 p_imu_cam = Vec3::Zero();  // [m]
};

// What one iteration did with one measurement of its frame: one status per
// measurement, as PX4's ekf2 fills one per aid source
// (updateAidSourceStatus), so that consumers (the ~refine recorder,
// eskf_recording.hpp) observe the filter's decisions instead of guessing them.
struct MeasurementOutcome {
  enum class Result : uint8_t {
    kNotProcessed,   // the frame stopped before its association (input or back-end error)
    kHeldBack,       // relocalising: the frame was held back (prediction only)
    kFused,          // in the joint update, applied
    kUpdateSkipped,  // in the joint update, which was skipped (S not PD)
    kNotUpdated,     // associated, beyond max_update_landmarks
    kAdded,          // started landmark_id
    kNotAdded,       // could start a landmark, beyond max_new_landmarks or the pool's room
    kNotAssociated,  // resembles a pool landmark but failed the ratio test, RANSAC, the gate or lost
                     // its landmark to another measurement: neither used nor added (Association::may_add)
  };
  int measurement = -1;      // index in the frame
  Result result = Result::kNotProcessed;
  bool associated = false;   // passed the descriptor match, RANSAC and the Mahalanobis gate
  uint64_t landmark_id = 0;  // the associated or started landmark; 0: none
  // Associated: the gate's squared Mahalanobis distance of the innovation
  // with this landmark alone, nu^T S_j^-1 nu (association.hpp); else NaN.
  double nis = std::numeric_limits<double>::quiet_NaN();
  Mat3 Cz = Mat3::Zero();    // C_z as the filter used it (re-detection term included)

  bool fused() const { return result == Result::kFused; }
  bool added() const { return result == Result::kAdded; }
};

// A frame's still test (eskf/still_frame_detector.hpp).
struct StillFrameVerdict {
  bool still = false;
  int common = 0;  // landmarks this frame associated that the previous frame saw
  double median_speed = std::numeric_limits<double>::quiet_NaN();  // [m/s] across the rays
};

// What a frame's zero-velocity update did (eskf/zero_velocity_update.hpp),
// as PX4 ekf2's aid-source status: tested on a still frame, fused unless its
// test ratio exceeded 1.
struct ZeroVelocityStatus {
  StillFrameVerdict still;
  bool tested = false;
  bool fused = false;
  Vec3 innovation = Vec3::Zero();           // 0 - v_hat [m/s]
  Vec3 innovation_variance = Vec3::Zero();  // diag of S = C_vv + R [m^2/s^2]
  double test_ratio = std::numeric_limits<double>::quiet_NaN();  // NIS / gate_chi2
};

// Per-iteration figures for diagnostics and the benchmark (milliseconds).
struct IterationReport {
  double t_predict_ms = 0, t_association_ms = 0, t_update_ms = 0, t_removal_ms = 0, t_addition_ms = 0,
         t_total_ms = 0;
  int n_measurements = 0;  // in the frame
  int n_candidates = 0;    // descriptor matches before gating
  int n_gated_out = 0;     // rejected by the Mahalanobis gate
  int n_updated = 0;       // used in the update (<= max_update_landmarks)
  int n_added = 0, n_removed = 0;
  int n_landmarks = 0;     // pool size after the iteration
  double mean_nis = 0;     // mean normalised innovation squared of the used measurements
  bool update_skipped = false;  // S not PD etc.: state left unchanged
  bool relocalised = false;     // pose mean moved to the map fit after an outage (settings relocalise_gap)
  bool relocalising = false;    // after an outage, no map fit yet: prediction only (no update, no additions)
  bool keyframe_fit = false;    // relocalised on a keyframe of the loaded map (Eskf::loadMap), not its landmarks
  bool vision_led = false;      // IMU and vision disagreed: pose means moved to the map fit (scene_motion_monitor.hpp)
  bool scene_moving = false;    // ... and the IMU says the device was still: the scanned surface moves
  ZeroVelocityStatus zero_velocity;
  // One per measurement of the frame, in frame order (back ends on the
  // ES-EKF's host logic; empty from the others).
  std::vector<MeasurementOutcome> measurements;

  // Adds the per-frame amounts of `o` (timings, counts, mean_nis), so that a
  // sum over frames divided by their number is the per-frame mean. The pool
  // size n_landmarks, the flags and the outcomes describe one frame, not an
  // amount: they are left as they are.
  IterationReport& operator+=(const IterationReport& o) {
    t_predict_ms += o.t_predict_ms;
    t_association_ms += o.t_association_ms;
    t_update_ms += o.t_update_ms;
    t_removal_ms += o.t_removal_ms;
    t_addition_ms += o.t_addition_ms;
    t_total_ms += o.t_total_ms;
    n_measurements += o.n_measurements;
    n_candidates += o.n_candidates;
    n_gated_out += o.n_gated_out;
    n_updated += o.n_updated;
    n_added += o.n_added;
    n_removed += o.n_removed;
    mean_nis += o.mean_nis;
    return *this;
  }
};

}  // namespace hapi_eskf
