// The error-state EKF over the motion model's pose block + landmark pool
// (docs/DESIGN.md "Filter"). Host side: nominal state, landmark bookkeeping
// (LandmarkBook), Jacobians, the shared association (association.hpp) and
// relocalisation (relocaliser.hpp). The covariance and the descriptors live
// in a CovarianceBackend (CPU or GPU; the SEIF's information storage,
// seif/seif_storage.hpp, behind the same contract); the pose block is the
// MotionModel's (motion_model.hpp). One SlamBackend (slam_backend.hpp):
// backend_algorithm eskf, and seif with the information storage.
//
// One processFrame() = predict to the frame stamp -> associate (descriptor
// best/second-best + ratio test, RANSAC rigid fit, Mahalanobis gate) -> IMU
// and vision agreement (scene_motion_monitor.hpp), relocalise or let vision
// lead (the map fit moves the pose, associate again) -> joint update with at
// most max_update_landmarks -> remove (stale landmarks when the pool would
// overflow) -> add at most max_new_landmarks unmatched measurements. Each
// stage is one private member; the report says what each measurement
// became (IterationReport::measurements).
#pragma once

#include "hapi_eskf/backend/landmark_book.hpp"
#include "hapi_eskf/backend/relocaliser.hpp"
#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/calibration_block.hpp"
#include "hapi_eskf/eskf/frame_error_block.hpp"
#include "hapi_eskf/eskf/imu_noise_estimator.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/eskf/scene_motion_monitor.hpp"
#include "hapi_eskf/eskf/still_frame_detector.hpp"
#include "hapi_eskf/eskf/zero_velocity_update.hpp"
#include "hapi_eskf/keyframes/keyframe_relocaliser.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hapi_eskf {

class Eskf final : public SlamBackend {
 public:
  // The backend's capacity must equal settings.max_landmarks and its pose
  // block the filter's (filterPoseDim: the motion model's, plus the
  // frame-error rows when modelled). `extrinsic`
  // is the camera in the IMU frame (models with IMU; setCameraExtrinsic()
  // changes it later).
  Eskf(const EskfSettings& settings, std::unique_ptr<CovarianceBackend> backend,
       const CameraExtrinsic& extrinsic = CameraExtrinsic());

  // Clears the pool; the camera starts at `initial` with the initial sigmas
  // of the settings. The next frame must have stamp >= `stamp`. The inertial
  // model then first aligns to gravity (addImu(), inertial_alignment.hpp):
  // until alignment_window of samples arrived, frames return kAwaitingImu
  // and `initial` is replaced by the gravity-aligned start. The constructor
  // resets to the identity pose at 0; until a reset succeeds (invalid
  // settings, backend capacity or pose block mismatch) every other operation
  // returns kNotInitialised (kBackendUnavailable without a backend).
  Status reset(const PoseState& initial, double stamp) override;

  // The camera in the IMU frame. The camera pose is kept (the inertial
  // model's body pose moves with the new extrinsic); a calibrated extrinsic
  // restarts from it as its prior (docs/DESIGN.md "Online calibration").
  // kNonFinite, kInvalidArgument (R not a rotation).
  Status setCameraExtrinsic(const CameraExtrinsic& extrinsic) override;

  // Prediction without a new IMU sample to `stamp` (no-op when stamp ==
  // current; constant velocity, or the inertial model's last sample held).
  // kInvalidArgument when stamp is earlier than the filter time.
  Status predictTo(double stamp) override;

  // One IMU sample (IMU frame, stamp on the camera clock:
  // imuSampleOnCameraClock; with the time offset calibrated, the filter
  // moves it to the estimated offset's clock, MotionModel::onEstimatedClock). Its covariance step is chained with the other
  // samples' and reaches the backend with the next frame or predictTo()
  // (poseCovariance() includes it at once). constant_velocity: kInvalidArgument (no IMU in
  // the model). gyro and inertial: a prediction step to the sample's stamp
  // with it (motion_model.hpp predictStep); before the inertial model is
  // aligned the sample goes to the alignment window instead. kNonFinite,
  // kInvalidArgument (stamp before the filter time); state unchanged on error.
  Status addImu(const ImuSample& sample) override;

  // One filter iteration. On any input error (kNonFinite, kDuplicateId,
  // kCapacityExceeded, kInvalidArgument, kEmptyInput for a frame without
  // measurements, kNotPositiveDefinite for a non-PD measurement covariance,
  // kAwaitingImu before the inertial alignment) the state is unchanged. The
  // one exception is a joint innovation covariance S found not PD inside the
  // update: the update is skipped (report->update_skipped), the prediction
  // and bookkeeping still apply, and kNotPositiveDefinite is returned (see
  // src/eskf/eskf.cpp).
  Status processFrame(const StereoFrame& frame, IterationReport* report = nullptr) override;

  // The left camera: pose in the world, camera-frame velocities.
  PoseState pose() const override { return model_->camera(state_); }
  // The camera as the last processed frame saw it, from which its new
  // landmarks were placed (m = p + R z): pose() plus the estimate of the
  // frame's shared vision error (frame_error_block.hpp); pose() when none is
  // modelled or the frame had no update.
  const PoseState& frameCamera() const { return frame_camera_; }
  // Its covariance in the camera-state layout [dp, dtheta, dv, dw] (12 x 12),
  // mapped from the state's (MotionModel::cameraStateJacobian).
  Mat12 cameraCovariance() const override;
  Mat6 cameraPoseCovariance() const override { return cameraCovariance().topLeftCorner<6, 6>(); }
  // The motion model's pose block of the state covariance (P x P).
  PoseMat poseCovariance() const;
  // The online calibration as estimated (calibration_block.hpp).
  CalibrationEstimate calibration() const;
  // The IMU's in-situ noise densities the prediction uses since the last
  // frame (imu_noise_estimator.hpp; zero: not measured, or
  // imu_noise_in_situ off).
  const ImuNoiseDensity& imuNoise() const { return state_.imu_noise; }
  const NominalState& state() const { return state_; }
  const MotionModel& motionModel() const { return *model_; }
  bool awaitingAlignment() const { return awaiting_alignment_; }
  double time() const override { return time_; }
  int numLandmarks() const override { return book_.size(); }
  std::vector<LandmarkInfo> landmarks() const override;  // with marginal covariances
  // The pool's descriptors, landmarks() order (numLandmarks() * length bytes).
  std::vector<uint8_t> landmarkDescriptors() const;

  // Puts a saved map into the pool right after reset() (empty pool): each
  // landmark with its covariance and no correlation with the pose, the world
  // frame becoming the map's. The camera's place in it is unknown: the pose
  // covariance widens (kLoadedMapPoseSigma*), and every frame is held back
  // (prediction only) until a RANSAC fit of >= kMapRelocaliseMinInliers
  // places the camera in the map (awaitingMap()). Then tracking goes on as
  // usual and new landmarks join the loaded ones, which the pool evicts
  // like any other (their saved observation counts, last seen at the load).
  // The inertial model needs the map's gravity direction (world frame, unit,
  // pointing down; map_file::MapData::gravity_direction) and a filter still
  // awaiting its alignment: the map is kept until the alignment, which then
  // turns its gravity-aligned world onto the map's gravity (docs/DESIGN.md
  // "Map file"), and a fit must agree with the IMU's tilt
  // (kMapRelocaliseMaxTilt); the yaw and position come from the fit.
  // The map's keyframes (map frame) place the camera where its landmarks
  // give no fit (an area whose landmarks were evicted before the save):
  // the placing keyframe's points join the pool as landmarks
  // (keyframeLandmarks, as many as leave room for max_new_landmarks) and
  // the frame is associated again at the keyframe fit, so its update ties
  // the pose to them (IterationReport::keyframe_fit).
  // kNotInitialised, kInvalidArgument (not freshly reset, descriptor length
  // of a landmark or keyframe, a keyframe's arrays, RANSAC off, inertial
  // without gravity direction), kCapacityExceeded (more than max_landmarks -
  // max_new_landmarks landmarks), kNonFinite / kNotPositiveDefinite (a
  // landmark); the filter is reset again on any error after the first
  // change, so nothing is loaded half.
  Status loadMap(const std::vector<PriorLandmark>& map, const Vec3& gravity_direction = Vec3::Zero(),
                 std::vector<Keyframe> keyframes = {});
  std::size_t mapKeyframes() const { return map_keyframes_.keyframes().size(); }
  bool awaitingMap() const { return relocaliser_.awaitingMap() || !pending_map_.empty(); }
  static constexpr double kLoadedMapPoseSigmaP = 0.1;      // [m]
  static constexpr double kLoadedMapPoseSigmaTheta = 0.3;  // [rad]
  const std::vector<Vec3>& landmarkPositions() const { return book_.positions(); }
  const std::vector<uint64_t>& landmarkIds() const { return book_.ids(); }
  const EskfSettings& settings() const { return settings_; }
  const CovarianceBackend& backend() const { return *backend_; }
  CovarianceBackend& mutableBackend() { return *backend_; }  // tests and benchmark

  // SlamBackend: the algorithm is the settings' backend_algorithm (eskf, or
  // seif with the information storage), the storage the backend's name.
  const char* name() const override { return toString(settings_.backend_algorithm); }
  std::string storage() const override { return backend_ ? backend_->name() : "none"; }
  std::string lastError() const override { return backend_ ? backend_->lastError() : std::string(); }
  std::size_t memoryBytes() const override { return backend_ ? backend_->memoryBytes() : 0; }
  bool supportsImu() const override { return model_->usesImu(); }
  bool poseBlockState(PoseBlockState* out) const override;

 private:
  // Internal steps, exposed to tests through the public API only.
  // One frame's working data, handed from stage to stage (eskf.cpp).
  struct FrameWork;
  // Everything that can be wrong before any change: the filter's state and
  // the frame itself.
  Status admitFrame(const StereoFrame& frame) const;
  // The frame with the filter's measurement model: C_z plus the re-detection
  // covariance (EskfSettings::measurement_angular_sigma); `frame` itself
  // when there is none, else a copy in *storage.
  const StereoFrame& withRedetectionNoise(const StereoFrame& frame, StereoFrame* storage) const;
  // The frame's stages, in processFrame() order. Each returns the Status
  // that ends the frame (kOk: go on).
  Status predictFrame(FrameWork& w);
  Status associateFrame(FrameWork& w);
  Status associateAtPose(FrameWork& w) const;
  Status checkSceneMotion(FrameWork& w, bool* vision_leads);
  Status moveToMapFit(FrameWork& w, bool vision_leads);
  void recordAssociation(FrameWork& w) const;
  Status updateFrame(FrameWork& w);
  std::vector<MeasurementBlock> updateBlocks(const FrameWork& w, const std::vector<int>& used_meas) const;
  Status fuse(FrameWork& w, const std::vector<int>& used_meas);
  Status removeForAdditions(FrameWork& w);
  Status addLandmarks(FrameWork& w);
  Status startLandmarks(FrameWork& w);
  // The zero-velocity update (zero_velocity_update.hpp): with these settings and model.
  bool zeroVelocityUsed() const;
  // A still frame's zero-velocity update, before its vision update.
  Status updateIfStill(FrameWork& w);
  // The frame's sightings for the next frame's still test.
  void rememberSightings(const FrameWork& w);
  // Every exit: closes the frame's backend work and hands out the report.
  Status finishFrame(FrameWork& w, Status s, IterationReport* report);
  Status predictStepTo(double stamp, const ImuSample* imu);
  // The held IMU samples (held_imu_) with stamps up to `up_to`, in order.
  Status predictHeldImu(double up_to);
  Status flushPrediction();  // the chained steps into the backend's C
  void clearPendingPrediction();
  // First estimates of the pose block (settings first_estimate_jacobians):
  // restart at the current state (after a reset, an alignment or a move of
  // the means), or follow a committed prediction step (gravity keeps its
  // first estimate).
  void restartFirstEstimates() { lin_ = state_; }
  // The in-situ noise measured so far becomes the one the steps until the
  // next frame assume (NominalState::imu_noise): set once per frame, so the
  // IMU-rate copy steps as the filter does.
  void refreshImuNoise();
  void advanceFirstEstimates();
  Status align();
  // The first frame after the alignment: the alignment again, over the
  // samples from the window's start up to the frame (docs/DESIGN.md
  // "Inertial initialisation": the world is the first camera's).
  Status realignAtFirstFrame(double stamp);
  // A sample after the alignment into held_imu_ (on the estimated clock).
  void holdImu(const ImuSample& sample);
  // loadMap's checks of the map before any change.
  Status checkMap(const std::vector<PriorLandmark>& map, const Vec3& gravity_direction) const;
  // The map into the pool, the pose block restarting from C_start widened.
  Status applyMap(const std::vector<PriorLandmark>& map, const PoseMat& C_start);
  // Landmarks with their own covariance, uncorrelated with the state, into
  // the pool (a loaded map, a placing keyframe's points).
  Status addPriorLandmarks(const std::vector<PriorLandmark>& landmarks);
  // Awaiting the map, with no landmark fit: the map keyframes' fit as the
  // frame's map fit (w.assoc.fit_*), the placing keyframe's points added to
  // the pool. False when no keyframe places the frame.
  bool fitOnMapKeyframes(FrameWork& w);
  // Whether this keyframe placement agrees with the previous frame's
  // (kKeyframeConfirm*; a frame without one breaks the chain); it becomes
  // the one the next frame is checked against.
  bool confirmKeyframeFit(const Eigen::Isometry3d& T_map_cam, double stamp);
  // The gravity-aligned world turned onto the map's gravity direction.
  void turnWorldTo(const Vec3& gravity_direction);
  // A map fit's camera tilt against the IMU's (kMapRelocaliseMaxTilt).
  bool tiltAgrees(const Mat3& R_fit) const;
  // The camera Jacobian of the pose block's first 6 columns as they are now
  // (the identity while the calibration's transition is open).
  Mat6 frameCameraJacobian(const NominalState& x) const { return calibration_.cameraJacobian(*model_, x); }
  // The extrinsic rows of the covariance back to their prior, uncorrelated.
  Status restartExtrinsicPrior();

  EskfSettings settings_;
  std::unique_ptr<CovarianceBackend> backend_;
  std::unique_ptr<MotionModel> model_;
  FrameErrorBlock frame_error_;
  CalibrationBlock calibration_;
  NominalState state_;
  PoseState frame_camera_;  // frameCamera()
  // The pose block's first estimates (docs/DESIGN.md "First-estimate
  // Jacobians"): the state as predicted, not corrected since; gravity as
  // first estimated.
  NominalState lin_;
  double time_ = 0.0;
  // Prediction steps not yet applied to the backend's C (predictStepTo):
  // their chained transition and noise; poseCovariance() includes them.
  PoseMat pending_F_, pending_Q_;
  bool pending_steps_ = false;
  bool initialised_ = false;
  // Inertial model: samples collected for the gravity alignment until it is done.
  bool awaiting_alignment_ = false;
  std::vector<ImuSample> alignment_samples_;
  // From the alignment to the first frame: every sample since the window
  // opened (realignAtFirstFrame), as read.
  bool realign_at_first_frame_ = false;
  std::vector<ImuSample> start_samples_;
  // Inertial model: a map loaded before the alignment, applied by it.
  std::vector<PriorLandmark> pending_map_;
  Vec3 pending_gravity_ = Vec3::Zero();
  // Samples on the estimated offset's clock (MotionModel::onEstimatedClock)
  // not yet predicted with: one the offset moved later than its configured
  // stamp waits until a sample or frame at least as late arrives, since the
  // caller hands in every sample up to a frame's stamp before the frame.
  std::vector<ImuSample> held_imu_;
  bool velocity_measured_ = false;  // PoseBlockState::velocity_measured
  ImuNoiseEstimator imu_noise_;  // every accepted sample, as read
  SceneMotionMonitor scene_motion_;
  StillFrameDetector still_;
  IntervalVelocity still_interval_;  // the nominal velocity's mean since the still test's previous frame
  ZeroVelocityUpdate zero_velocity_;
  Relocaliser relocaliser_;
  KeyframeRelocaliser map_keyframes_;  // the loaded map's keyframes (loadMap)
  // The last frame's keyframe placement, awaiting the next one's agreement.
  std::optional<std::pair<double, Eigen::Isometry3d>> keyframe_candidate_;
  LandmarkBook book_;  // per slot, same order as the backend's slots
};

// The ES-EKF's maker (backend/slam_backend_maker.hpp): backend_algorithm eskf,
// the filter over the storage the settings name (storage_factory.hpp).
std::unique_ptr<SlamBackend> makeEskfBackend(const EskfSettings& settings, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace hapi_eskf
