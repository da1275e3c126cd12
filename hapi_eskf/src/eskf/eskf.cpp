// Host side of the filter: nominal state, bookkeeping and the iteration of
// docs/DESIGN.md "One iteration". The covariance lives in the backend.
//
// Policies (documented choices):
//  * An empty frame returns kEmptyInput and does nothing (not even predict):
//    every non-kOk return leaves the state unchanged, and nothing is lost
//    because the next frame predicts over the whole interval.
//  * Which measurements update, which are added, which landmarks go when the
//    pool is full: the shared bookkeeping policy (landmark_book.hpp).
//  * The one error detected after state changes: a joint S that is not PD (or
//    a non-finite correction) in the update. The update is then skipped
//    (report.update_skipped), the prediction and the bookkeeping of this frame
//    still apply (the state stays a consistent predicted state) and
//    processFrame returns kNotPositiveDefinite.
//  * The ESKF reset Jacobian (I - [dtheta/2]x on the orientation block after
//    injection) is taken as identity, as usual for small corrections.
#include "hapi_eskf/eskf/eskf.hpp"

#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/backend/stereo_frame_check.hpp"
#include "hapi_eskf/covariance_checks.hpp"
#include "hapi_eskf/eskf/inertial_alignment.hpp"
#include "hapi_eskf/so3.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_set>

namespace hapi_eskf {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Relocalising: the frame is held back (prediction only).
void holdBack(IterationReport* rep) {
  rep->relocalising = true;
  for (MeasurementOutcome& o : rep->measurements) o.result = MeasurementOutcome::Result::kHeldBack;
}

// A loaded map's keyframes place a camera with the map fit's RANSAC and
// inlier count (association settings, kMapRelocaliseMinInliers).
KeyframeRelocaliserSettings mapKeyframeSettings(const EskfSettings& s) {
  KeyframeRelocaliserSettings k;
  k.ransac_iterations = s.ransac_iterations;
  k.min_inliers = kMapRelocaliseMinInliers;
  return k;
}

}  // namespace

Eskf::Eskf(const EskfSettings& settings, std::unique_ptr<CovarianceBackend> backend,
           const CameraExtrinsic& extrinsic)
    : settings_(settings),
      backend_(std::move(backend)),
      model_(makeMotionModel(settings, extrinsic)),
      frame_error_(model_->poseDim(), settings),
      calibration_(*model_),
      imu_noise_(settings.imu_noise_window),
      scene_motion_(settings),
      still_(settings.still_max_speed),
      zero_velocity_(settings.still_velocity_sigma, settings.gate_chi2, frame_error_.filterDim()),
      relocaliser_(settings),
      map_keyframes_(mapKeyframeSettings(settings)) {
  // Construction never throws; a mismatch is reported by reset()/processFrame().
  if (backend_ && settings_.validate().empty() && backend_->capacity() == settings_.max_landmarks &&
      backend_->poseDim() == frame_error_.filterDim())
    reset(PoseState(), 0.0);
}

Status Eskf::reset(const PoseState& initial, double stamp) {
  if (!backend_) return Status::kBackendUnavailable;
  if (!settings_.validate().empty()) return Status::kInvalidArgument;
  if (backend_->capacity() != settings_.max_landmarks || backend_->poseDim() != frame_error_.filterDim())
    return Status::kInvalidArgument;
  if (!std::isfinite(stamp) || !initial.p.allFinite() || !initial.q.coeffs().allFinite() || !initial.v.allFinite() ||
      !initial.w.allFinite())
    return Status::kNonFinite;
  if (initial.q.norm() < 1e-6) return Status::kInvalidArgument;
  const Status st = backend_->reset(frame_error_.covariance(model_->initialCovariance()));
  if (st != Status::kOk) return st;
  frame_error_.discard();
  calibration_.discard();
  held_imu_.clear();
  clearPendingPrediction();
  PoseState camera = initial;
  camera.q.normalize();
  state_ = model_->fromCamera(camera);
  frame_camera_ = model_->camera(state_);
  restartFirstEstimates();
  time_ = stamp;
  relocaliser_.reset(stamp);
  velocity_measured_ = false;  // the initial velocity is a guess
  awaiting_alignment_ = model_->kind() == MotionModelKind::kInertial;
  alignment_samples_.clear();
  realign_at_first_frame_ = false;
  start_samples_.clear();
  pending_map_.clear();
  map_keyframes_.clear();
  keyframe_candidate_.reset();
  imu_noise_.clear();
  scene_motion_.reset();
  still_.reset();
  still_interval_.restart();
  initialised_ = true;
  book_.clear();
  return Status::kOk;
}

Status Eskf::setCameraExtrinsic(const CameraExtrinsic& extrinsic) {
  if (!extrinsic.R_imu_cam.allFinite() || !extrinsic.p_imu_cam.allFinite()) return Status::kNonFinite;
  if (!isRotation(extrinsic.R_imu_cam)) return Status::kInvalidArgument;
  const PoseState camera = pose();
  model_ = makeMotionModel(settings_, extrinsic);
  state_.R_bc = extrinsic.R_imu_cam;
  state_.p_bc = extrinsic.p_imu_cam;
  model_->moveCameraTo(&state_, camera.p, camera.q);
  restartFirstEstimates();
  return restartExtrinsicPrior();
}

// The pending prediction steps commute with this transition: their F is
// the identity on the calibration rows and zero between them and the rest.
Status Eskf::restartExtrinsicPrior() {
  const int e = model_->calibration().extrinsic;
  if (e < 0 || !initialised_ || !backend_) return Status::kOk;
  const int P = model_->poseDim();
  PoseMat F = PoseMat::Identity(P, P), Q = PoseMat::Zero(P, P);
  F.block(e, e, kCalibExtrinsicDim, kCalibExtrinsicDim).setZero();
  Q.block(e, e, kCalibExtrinsicDim, kCalibExtrinsicDim) =
      model_->initialCovariance().block(e, e, kCalibExtrinsicDim, kCalibExtrinsicDim);
  return backend_->predict(frame_error_.transition(F), frame_error_.noise(Q));
}

// One transactional step of the model. The covariance part is deferred
// (docs/DESIGN.md "Inertial prediction", deferred cross-covariance): the
// steps' transitions are chained, Phi <- F Phi and Q_acc <- F Q_acc F^T + Q,
// and applied to C in one backend call when C is next needed
// (flushPrediction), C_pp <- Phi C_pp Phi^T + Q_acc and C_pm <- Phi C_pm:
// exactly the sequence of single steps, but the O(K) cross-block product
// runs once per frame instead of once per IMU sample.
Status Eskf::predictStepTo(double stamp, const ImuSample* imu) {
  const NominalState* lin = settings_.first_estimate_jacobians ? &lin_ : nullptr;
  const Vec3 v_before = state_.v;
  const double t_before = time_;
  const Status st = predictStep(*model_, &state_, &time_, stamp, imu, [this](const PoseMat& F, const PoseMat& Q) {
    const PoseMat F_acc = F * pending_F_;
    PoseMat Q_acc = F * pending_Q_ * F.transpose() + Q;
    Q_acc = (0.5 * (Q_acc + Q_acc.transpose())).eval();
    if (!F_acc.allFinite() || !Q_acc.allFinite()) return Status::kNonFinite;
    pending_F_ = F_acc;
    pending_Q_ = Q_acc;
    pending_steps_ = true;
    return Status::kOk;
  }, lin);
  if (st != Status::kOk) return st;
  advanceFirstEstimates();
  still_interval_.add(t_before, v_before, time_, state_.v);
  return st;
}

void Eskf::advanceFirstEstimates() {
  const Vec3 g = lin_.g;
  lin_ = state_;
  lin_.g = g;
}

Status Eskf::flushPrediction() {
  if (!pending_steps_) return Status::kOk;
  const Status st = backend_->predict(frame_error_.transition(pending_F_), frame_error_.noise(pending_Q_));
  if (st == Status::kOk) clearPendingPrediction();
  return st;
}

void Eskf::clearPendingPrediction() {
  const int P = model_->poseDim();
  pending_F_ = PoseMat::Identity(P, P);
  pending_Q_ = PoseMat::Zero(P, P);
  pending_steps_ = false;
}

Status Eskf::predictTo(double stamp) {
  if (!initialised_) return Status::kNotInitialised;
  if (awaiting_alignment_) return Status::kAwaitingImu;
  Status st = predictHeldImu(stamp);
  if (st == Status::kOk) st = predictStepTo(stamp, nullptr);
  return st == Status::kOk ? flushPrediction() : st;
}

Status Eskf::addImu(const ImuSample& sample) {
  if (!initialised_) return Status::kNotInitialised;
  if (!std::isfinite(sample.stamp) || !sample.gyro.allFinite() || !sample.accel.allFinite())
    return Status::kNonFinite;
  if (!model_->usesImu() || sample.stamp < time_) return Status::kInvalidArgument;
  if (awaiting_alignment_) {
    if (!alignment_samples_.empty() && sample.stamp <= alignment_samples_.back().stamp)
      return Status::kInvalidArgument;
    if (settings_.imu_noise_in_situ) imu_noise_.add(sample);
    alignment_samples_.push_back(sample);
    if (sample.stamp - alignment_samples_.front().stamp >= settings_.alignment_window) return align();
    return Status::kOk;
  }
  if (settings_.imu_noise_in_situ) imu_noise_.add(sample);
  if (realign_at_first_frame_) start_samples_.push_back(sample);
  holdImu(sample);
  return predictHeldImu(sample.stamp);
}

void Eskf::holdImu(const ImuSample& sample) {
  ImuSample moved = model_->onEstimatedClock(sample, state_);
  if (!held_imu_.empty()) moved.stamp = std::max(moved.stamp, held_imu_.back().stamp);
  held_imu_.push_back(moved);
}

// In order; a sample an offset correction moved before the filter time is
// dropped (its interval was predicted with the previous sample). A failed
// step drops its sample too (the state is unchanged by it).
Status Eskf::predictHeldImu(double up_to) {
  std::size_t n = 0;
  Status st = Status::kOk;
  while (n < held_imu_.size() && held_imu_[n].stamp <= up_to) {
    const ImuSample& m = held_imu_[n++];
    if (m.stamp < time_) continue;
    st = predictStepTo(m.stamp, &m);
    if (st != Status::kOk) break;
    scene_motion_.addImu(m, state_.b_g);
  }
  held_imu_.erase(held_imu_.begin(), held_imu_.begin() + static_cast<std::ptrdiff_t>(n));
  return st;
}

// The gravity-aligned start replaces the pose given to reset(); the pool is
// still empty (frames wait for the alignment), so only the pose block changes.
Status Eskf::align() {
  InertialStart start;
  Status st = alignInertialStart(alignment_samples_, *model_, settings_, &start);
  if (st == Status::kEmptyInput) {
    alignment_samples_.clear();  // no usable direction: collect a new window
    return st;
  }
  if (st != Status::kOk) return st;
  st = backend_->reset(frame_error_.covariance(start.C));
  if (st != Status::kOk) return st;
  frame_error_.discard();
  calibration_.discard();
  held_imu_.clear();
  clearPendingPrediction();
  state_ = start.x;
  refreshImuNoise();
  restartFirstEstimates();
  time_ = alignment_samples_.back().stamp;
  relocaliser_.reset(time_);
  for (const ImuSample& m : alignment_samples_) scene_motion_.addImu(m, state_.b_g);
  // A loaded map is placed by this alignment; without one the first frame
  // aligns again over its own window.
  realign_at_first_frame_ = pending_map_.empty();
  start_samples_ = realign_at_first_frame_ ? std::move(alignment_samples_) : std::vector<ImuSample>();
  alignment_samples_.clear();
  awaiting_alignment_ = false;
  velocity_measured_ = start.still;  // zero, measured by the still window
  if (pending_map_.empty()) return Status::kOk;
  std::vector<PriorLandmark> map;
  map.swap(pending_map_);
  turnWorldTo(pending_gravity_);
  return applyMap(map, start.C);
}

// The alignment's state sits at its window's last sample, and the first
// frame comes up to a frame interval later. Predicted over that gap, the
// first camera would carry the gap's share of a moving start's velocity and
// gyro-bias uncertainty (0.2 m/s and 0.1 rad/s over 0.1 s: 2-3 cm and
// 0.6 deg), and so would every landmark the frame starts: the map would
// rest on a pose whose position and turn nothing observes, and the
// linearised updates of the next frames turn pose and map together (0.5 deg
// and 4-8 mm over EuRoC's standstill). So the first frame aligns again, over
// the window grown up to its stamp, and the world is that camera's (docs/
// DESIGN.md "Inertial initialisation"). The alignment decides still or
// moving again over the longer window. Without landmarks in the pool the
// pose block is all there is to restart; a map loaded before the alignment
// was placed by it and stays.
Status Eskf::realignAtFirstFrame(double stamp) {
  if (!realign_at_first_frame_) return Status::kOk;
  realign_at_first_frame_ = false;
  std::vector<ImuSample> window, later;
  for (const ImuSample& m : start_samples_)
    (model_->onEstimatedClock(m, state_).stamp <= stamp ? window : later).push_back(m);
  start_samples_.clear();
  if (book_.size() != 0 || window.size() < 2) return Status::kOk;
  // The in-situ noise has seen every sample once and keeps them.
  alignment_samples_ = std::move(window);
  scene_motion_.reset();
  Status st = align();
  realign_at_first_frame_ = false;
  start_samples_.clear();
  // No direction over the longer window (align() changed nothing): the
  // state predicted from the first alignment goes on.
  if (st == Status::kEmptyInput) return Status::kOk;
  if (st != Status::kOk) return st;
  // Samples after the frame wait for the next one, as when they arrive.
  for (const ImuSample& m : later) holdImu(m);
  return Status::kOk;
}

void Eskf::refreshImuNoise() {
  if (settings_.imu_noise_in_situ && model_->usesImu()) state_.imu_noise = imu_noise_.estimate();
}

PoseMat Eskf::poseCovariance() const {
  if (!backend_) return PoseMat::Zero(model_->poseDim(), model_->poseDim());
  const PoseMat C = frame_error_.modelBlock(backend_->poseCovariance());
  return pending_steps_ ? predictPoseCovariance(C, pending_F_, pending_Q_) : C;
}

CalibrationEstimate Eskf::calibration() const {
  PoseBlockState s;
  if (!poseBlockState(&s)) return CalibrationEstimate();
  return calibrationEstimate(model_->calibration(), s);
}

Mat12 Eskf::cameraCovariance() const { return hapi_eskf::cameraCovariance(*model_, state_, poseCovariance()); }

std::vector<LandmarkInfo> Eskf::landmarks() const {
  if (!backend_) return book_.info({});
  return book_.info(backend_->landmarkCovariances());
}

std::vector<uint8_t> Eskf::landmarkDescriptors() const {
  return backend_ ? backend_->descriptors() : std::vector<uint8_t>();
}

Status Eskf::loadMap(const std::vector<PriorLandmark>& map, const Vec3& gravity_direction,
                     std::vector<Keyframe> keyframes) {
  if (!backend_) return Status::kBackendUnavailable;
  if (!initialised_) return Status::kNotInitialised;
  const Status st = checkMap(map, gravity_direction);
  if (st != Status::kOk) return st;
  for (Keyframe& k : keyframes) {
    if (k.descriptor_length == backend_->descriptorLength() && map_keyframes_.add(std::move(k))) continue;
    map_keyframes_.clear();
    return Status::kInvalidArgument;
  }
  if (model_->kind() != MotionModelKind::kInertial) return applyMap(map, model_->initialCovariance());
  pending_map_ = map;  // align() applies it
  pending_gravity_ = gravity_direction.normalized();
  return Status::kOk;
}

Status Eskf::checkMap(const std::vector<PriorLandmark>& map, const Vec3& gravity_direction) const {
  if (numLandmarks() != 0 || !pending_map_.empty() || !map_keyframes_.keyframes().empty() ||
      settings_.ransac_iterations == 0)
    return Status::kInvalidArgument;
  if (model_->kind() == MotionModelKind::kInertial &&
      (!awaiting_alignment_ || !gravity_direction.allFinite() || std::abs(gravity_direction.norm() - 1.0) > 1e-3))
    return Status::kInvalidArgument;
  if (static_cast<int>(map.size()) > settings_.max_landmarks - settings_.max_new_landmarks)
    return Status::kCapacityExceeded;
  for (const PriorLandmark& l : map) {
    if (static_cast<int>(l.descriptor.size()) != backend_->descriptorLength() || l.times_observed < 1)
      return Status::kInvalidArgument;
    if (!l.position.allFinite() || !l.covariance.allFinite()) return Status::kNonFinite;
    if (!isSymmetricPositiveDefinite(l.covariance)) return Status::kNotPositiveDefinite;
  }
  return Status::kOk;
}

Status Eskf::applyMap(const std::vector<PriorLandmark>& map, const PoseMat& C_start) {
  PoseMat C0 = C_start;
  C0.diagonal().segment<3>(kIdxP).array() += kLoadedMapPoseSigmaP * kLoadedMapPoseSigmaP;
  C0.diagonal().segment<3>(kIdxTheta).array() += kLoadedMapPoseSigmaTheta * kLoadedMapPoseSigmaTheta;
  Status st = backend_->reset(frame_error_.covariance(C0));
  if (st == Status::kOk) st = addPriorLandmarks(map);
  if (st != Status::kOk) {
    backend_->reset(frame_error_.covariance(C_start));
    map_keyframes_.clear();
    return st;
  }
  relocaliser_.awaitMap();
  return Status::kOk;
}

Status Eskf::addPriorLandmarks(const std::vector<PriorLandmark>& landmarks) {
  std::vector<NewLandmarkBlock> blocks(landmarks.size());
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    // m = position, dm = dz with C_z the landmark's own marginal: no pose columns.
    blocks[i].G_pose.setZero();
    blocks[i].G_z.setIdentity();
    blocks[i].Cz = landmarks[i].covariance;
    blocks[i].descriptor = landmarks[i].descriptor.data();
  }
  const Status st = backend_->addLandmarks(blocks);
  if (st != Status::kOk) return st;
  for (const PriorLandmark& l : landmarks) book_.addPrior(l.position, l.times_observed, time_);
  return Status::kOk;
}

// The alignment's world is z up at the first camera position with an
// arbitrary yaw; the map's is the saved one. Turning the first onto the
// second's gravity (smallest rotation) leaves only a yaw and a position
// unknown, which the map fit supplies. The alignment's covariance is
// isotropic in the world axes (inertial_alignment.cpp), so it is unchanged
// by the turn.
void Eskf::turnWorldTo(const Vec3& gravity_direction) {
  const Eigen::Quaterniond R = Eigen::Quaterniond::FromTwoVectors(state_.g.normalized(), gravity_direction);
  const PoseState camera = model_->camera(state_);
  state_.g = R * state_.g;
  state_.v = R * state_.v;
  model_->moveCameraTo(&state_, R * camera.p, (R * camera.q).normalized());
  restartFirstEstimates();
}

// The angle between the world's down in the fit's camera frame and in the
// predicted one's: yaw and position are free, the tilt is the IMU's.
bool Eskf::tiltAgrees(const Mat3& R_fit) const {
  const double g = state_.g.norm();
  if (!(g > 0)) return true;
  const Vec3 down = state_.g / g;
  const Vec3 seen = R_fit.transpose() * down;
  const Vec3 predicted = pose().q.conjugate() * down;
  const double angle = std::atan2(seen.cross(predicted).norm(), seen.dot(predicted));
  const double sigma_g = std::sqrt(poseCovariance().block<3, 3>(kIdxG, kIdxG).diagonal().maxCoeff());
  return angle <= std::max(kMapRelocaliseMaxTilt, 3.0 * sigma_g / g);
}

bool Eskf::poseBlockState(PoseBlockState* out) const {
  if (!out || !backend_ || !initialised_) return false;
  out->extrinsic = model_->extrinsic();
  out->x = state_;
  out->C = poseCovariance();
  out->time = time_;
  out->velocity_measured = velocity_measured_;
  return true;
}

// One frame's working data, handed from stage to stage. `frame` is the frame
// with the filter's measurement model (withRedetectionNoise), used for
// gating, the update and new landmarks alike.
struct Eskf::FrameWork {
  FrameWork(const StereoFrame& in, int n_landmarks) : frame(&in) {
    rep.n_measurements = static_cast<int>(in.measurements.size());
    rep.n_landmarks = n_landmarks;
    rep.measurements.resize(in.measurements.size());
    for (int i = 0; i < rep.n_measurements; ++i) rep.measurements[i].measurement = i;
  }
  const Clock::time_point start = Clock::now();
  IterationReport rep;
  StereoFrame inflated;  // withRedetectionNoise's copy
  const StereoFrame* frame;
  double previous_stamp = 0.0;  // the previous frame's (Relocaliser::acceptFrame)
  Association assoc;
  std::vector<int> by_response;  // LandmarkBook::byResponse
  std::vector<char> used_slot;   // the landmarks of this frame's update
  // The frame's predicted camera pose and its Jacobian: the update's
  // linearisation point, and with first-estimate Jacobians also the new
  // landmarks' (docs/DESIGN.md "First-estimate Jacobians").
  PoseState camera_predicted;
  Mat6 J_predicted = Mat6::Identity();
  // The state the frame saw: new landmarks are placed from it (with a
  // modelled frame error it differs from the corrected state by the
  // estimate of that error).
  NominalState frame_state;
  std::vector<int> add_meas;  // measurements that would start landmarks, strongest first
  int n_add = 0;              // how many of them fit
  Status result = Status::kOk;  // kNotPositiveDefinite once the update was skipped
};

Status Eskf::processFrame(const StereoFrame& frame_in, IterationReport* report) {
  FrameWork w(frame_in, numLandmarks());
  // Everything that can be wrong with the input is found here, before any change.
  Status st = admitFrame(frame_in);
  if (st == Status::kOk) st = realignAtFirstFrame(frame_in.stamp);
  if (st != Status::kOk) return finishFrame(w, st, report);
  w.frame = &withRedetectionNoise(frame_in, &w.inflated);
  // The samples held for the estimated time offset up to the frame.
  st = predictHeldImu(frame_in.stamp);
  if (st != Status::kOk) return finishFrame(w, st, report);

  // --- predict (from rest after an outage) ---
  st = predictFrame(w);
  // --- associate; relocalise or let vision lead ---
  if (st == Status::kOk) st = associateFrame(w);
  if (st != Status::kOk) return finishFrame(w, st, report);
  recordAssociation(w);
  if (relocaliser_.holdFrame(w.frame->stamp)) {
    holdBack(&w.rep);  // settings.hpp kRelocaliseWaitS: wait for a frame the map supports
    return finishFrame(w, Status::kOk, report);
  }
  // --- update, remove, add ---
  st = updateIfStill(w);
  if (st == Status::kOk) st = updateFrame(w);
  if (st == Status::kOk) st = removeForAdditions(w);
  if (st == Status::kOk) st = addLandmarks(w);
  rememberSightings(w);
  return finishFrame(w, st == Status::kOk ? w.result : st, report);
}

Status Eskf::admitFrame(const StereoFrame& frame) const {
  if (!backend_) return Status::kBackendUnavailable;
  if (!initialised_) return Status::kNotInitialised;
  if (awaiting_alignment_) return Status::kAwaitingImu;
  return checkStereoFrame(frame, time_, backend_->descriptorLength(), settings_.max_frame_measurements);
}

// Measurement model: C_z of the stereo pair plus the keypoint's re-detection
// noise across frames (settings.hpp, measurement_angular_sigma).
const StereoFrame& Eskf::withRedetectionNoise(const StereoFrame& frame, StereoFrame* storage) const {
  if (!(settings_.measurement_angular_sigma > 0.0)) return frame;
  *storage = frame;
  for (StereoMeasurement& m : storage->measurements)
    m.Cz += redetectionCovariance(m.z, settings_.measurement_angular_sigma);
  return *storage;
}

// After an outage longer than relocalise_gap the last velocity says nothing
// about the motion since: predict from rest (settings.hpp). A prediction
// that fails leaves the state as it was (the frame is rejected).
Status Eskf::predictFrame(FrameWork& w) {
  const double stamp = w.frame->stamp;
  const NominalState state_before = state_, lin_before = lin_;
  const bool velocity_measured_before = velocity_measured_;
  if (relocaliser_.beginFrame(stamp)) {
    model_->stop(&state_);
    restartFirstEstimates();
    velocity_measured_ = false;
  }
  const auto t0 = Clock::now();
  Status st = predictStepTo(stamp, nullptr);
  if (st == Status::kOk) st = flushPrediction();
  w.rep.t_predict_ms = msSince(t0);
  if (st != Status::kOk) {
    state_ = state_before;
    lin_ = lin_before;
    relocaliser_.rollback();
    velocity_measured_ = velocity_measured_before;
    return st;
  }
  w.previous_stamp = relocaliser_.acceptFrame(stamp);
  refreshImuNoise();
  // From here to finishFrame() the first 6 pose columns are the camera's
  // pose error (calibration_block.hpp) and the pose this frame sees, with
  // its shared vision error (frame_error_block.hpp).
  st = calibration_.open(backend_.get(), frame_error_, *model_, state_);
  if (st != Status::kOk) return st;
  return frame_error_.open(backend_.get(), frameCameraJacobian(state_));
}

Status Eskf::associateAtPose(FrameWork& w) const {
  return associate(*w.frame, pose(), frameCameraJacobian(state_), book_.positions(), *backend_, settings_,
                   &w.assoc);
}

// Association at the predicted pose; with an IMU, the IMU and vision
// agreement; after an outage, or when vision leads, the map fit moves the
// pose and the frame is associated again around it.
Status Eskf::associateFrame(FrameWork& w) {
  const auto t0 = Clock::now();
  Status st = associateAtPose(w);
  bool have_fit = st == Status::kOk && w.assoc.fit_inliers >= relocaliser_.minInliers() &&
                  (!relocaliser_.awaitingMap() || model_->kind() != MotionModelKind::kInertial ||
                   tiltAgrees(w.assoc.fit_R));
  if (st == Status::kOk && !have_fit && relocaliser_.awaitingMap()) have_fit = fitOnMapKeyframes(w);
  bool vision_leads = false;
  if (have_fit && model_->usesImu() && !relocaliser_.pending()) {
    const Status prior = checkSceneMotion(w, &vision_leads);
    if (prior != Status::kOk) return prior;
  }
  if (have_fit && (relocaliser_.pending() || vision_leads)) st = moveToMapFit(w, vision_leads);
  w.rep.t_association_ms = msSince(t0);
  if (st != Status::kOk) return st;
  w.rep.n_candidates = w.assoc.n_candidates;
  w.rep.n_gated_out = w.assoc.n_gated_out;
  return Status::kOk;
}

// IMU and vision agreement (models with IMU; scene_motion_monitor.hpp).
Status Eskf::checkSceneMotion(FrameWork& w, bool* vision_leads) {
  const SceneMotionVerdict v = scene_motion_.onFrame(w.assoc.fit_inliers, w.assoc.n_fit_inliers_gated_out);
  *vision_leads = v.disagreed;
  w.rep.vision_led = v.disagreed;
  w.rep.scene_moving = v.disagreed && v.device_still;
  // A moving device whose prediction vision contradicts: the motion states
  // (velocity, biases, gravity) are what is wrong (a start in a fast turn
  // levels the map by a mean acceleration, the velocity starts at rest):
  // their uncertainty goes back to the prior, so this frame's update and
  // the next ones estimate them afresh instead of keeping a wrong,
  // confident value that disagrees frame after frame.
  if (!v.disagreed || v.device_still) return Status::kOk;
  const int P = model_->poseDim();
  return backend_->predict(frame_error_.transition(PoseMat::Identity(P, P)),
                           frame_error_.noise(model_->motionStatesPrior()));
}

// The map fit becomes the linearisation point (means only), then gate again
// around it. After an outage the velocity was set to rest; when vision
// leads, the velocity mean takes the displacement the prediction missed
// over this frame interval, so the next prediction starts from a velocity
// vision supports (left alone, a wrong velocity makes every following frame
// disagree again).
Status Eskf::moveToMapFit(FrameWork& w, bool vision_leads) {
  const double stamp = w.frame->stamp;
  if (vision_leads && !relocaliser_.pending() && stamp > w.previous_stamp)
    model_->correctVelocity(&state_, w.assoc.fit_t - pose().p, stamp - w.previous_stamp, w.rep.scene_moving);
  // Placed in a loaded map, the world frame itself changed: the velocity
  // (the IMU's, in the turned alignment frame) turns with the camera.
  if (relocaliser_.awaitingMap()) state_.v = w.assoc.fit_R * pose().q.conjugate().toRotationMatrix() * state_.v;
  model_->moveCameraTo(&state_, w.assoc.fit_t, Eigen::Quaterniond(w.assoc.fit_R).normalized());
  restartFirstEstimates();
  w.rep.relocalised = relocaliser_.fitApplied();
  return associateAtPose(w);
}

// The loaded map's keyframes place the frame where its landmarks did not:
// the placing keyframe's points (as many as leave room for this frame's
// additions) join the pool, so the association again at the fitted pose
// (moveToMapFit) updates the pose against them. Without room the fit still
// moves the pose, and the loaded landmarks seen later tie it to the map.
bool Eskf::fitOnMapKeyframes(FrameWork& w) {
  const std::optional<KeyframeFit> fit = map_keyframes_.place(*w.frame);
  const bool placed = fit && (model_->kind() != MotionModelKind::kInertial || tiltAgrees(fit->T_map_cam.linear()));
  if (!placed) {
    keyframe_candidate_.reset();  // the next placement is checked against the frame after it
    return false;
  }
  if (!confirmKeyframeFit(fit->T_map_cam, w.frame->stamp)) return false;
  std::vector<PriorLandmark> points = keyframeLandmarks(map_keyframes_.keyframes()[fit->keyframe]);
  const long room = static_cast<long>(settings_.max_landmarks) - settings_.max_new_landmarks - numLandmarks();
  points.resize(static_cast<std::size_t>(std::clamp(room, 0L, static_cast<long>(points.size()))));
  // A failed addition leaves the pool as it was (the backend's contract):
  // the fit then moves the pose alone.
  static_cast<void>(addPriorLandmarks(points));
  w.assoc.fit_R = fit->T_map_cam.linear();
  w.assoc.fit_t = fit->T_map_cam.translation();
  w.assoc.fit_inliers = fit->inliers;
  w.rep.keyframe_fit = true;
  return true;
}

bool Eskf::confirmKeyframeFit(const Eigen::Isometry3d& T_map_cam, double stamp) {
  const auto previous = keyframe_candidate_;
  keyframe_candidate_ = std::make_pair(stamp, T_map_cam);
  if (!previous) return false;
  const double dt = stamp - previous->first;
  if (!(dt > 0.0) || dt > kRelocaliseWaitS) return false;
  const Eigen::Isometry3d moved = previous->second.inverse() * T_map_cam;
  const double angle = Eigen::AngleAxisd(moved.linear()).angle();
  return moved.translation().norm() <= kKeyframeConfirmTranslation + kKeyframeConfirmSpeed * dt &&
         angle <= kKeyframeConfirmRotation + kKeyframeConfirmRate * dt;
}

// Each measurement as the association left it; the update and the
// additions settle the associated and the new ones.
void Eskf::recordAssociation(FrameWork& w) const {
  using Result = MeasurementOutcome::Result;
  const Association& a = w.assoc;
  for (MeasurementOutcome& o : w.rep.measurements) {
    const int i = o.measurement;
    o.Cz = w.frame->measurements[i].Cz;
    o.associated = a.slot[i] >= 0;
    if (o.associated) {
      o.landmark_id = book_.ids()[a.slot[i]];
      o.nis = a.d2[i];
      o.result = Result::kNotUpdated;
    } else {
      o.result = a.may_add[i] ? Result::kNotAdded : Result::kNotAssociated;
    }
  }
}

Status Eskf::updateFrame(FrameWork& w) {
  w.by_response = LandmarkBook::byResponse(*w.frame);
  const auto t0 = Clock::now();
  const std::vector<int> used_meas = LandmarkBook::chooseUpdates(w.assoc, w.by_response, settings_);
  w.used_slot.assign(numLandmarks(), 0);
  w.camera_predicted = pose();
  w.J_predicted = frameCameraJacobian(state_);
  w.frame_state = state_;
  const Status st = used_meas.empty() ? Status::kOk : fuse(w, used_meas);
  w.rep.t_update_ms = msSince(t0);
  return st;
}

std::vector<MeasurementBlock> Eskf::updateBlocks(const FrameWork& w, const std::vector<int>& used_meas) const {
  const std::vector<Vec3>& lin_positions =
      settings_.first_estimate_jacobians ? book_.firstEstimates() : book_.positions();
  std::vector<MeasurementBlock> blocks(used_meas.size());
  for (std::size_t j = 0; j < used_meas.size(); ++j) {
    const int i = used_meas[j], k = w.assoc.slot[i];
    const StereoMeasurement& m = w.frame->measurements[i];
    MeasurementBlock& b = blocks[j];
    b.slot = k;
    Mat36 H_camera;
    measurementJacobian(w.camera_predicted, lin_positions[k], &H_camera, &b.H_landmark);
    b.H_pose = H_camera * w.J_predicted;
    b.R = m.Cz;
    b.innovation = m.z - measure(w.camera_predicted, book_.positions()[k]);
  }
  return blocks;
}

// The joint update of the chosen measurements. S not PD (or a non-finite
// correction): the update is skipped and the frame goes on (file header).
Status Eskf::fuse(FrameWork& w, const std::vector<int>& used_meas) {
  using Result = MeasurementOutcome::Result;
  Eigen::VectorXd dx;
  double nis = 0.0;
  const Status st = backend_->update(updateBlocks(w, used_meas), &dx, &nis);
  const bool skipped = st == Status::kNotPositiveDefinite || st == Status::kNonFinite;
  if (st != Status::kOk && !skipped) return st;
  // The landmarks were associated either way: protect them from eviction.
  for (int i : used_meas) {
    w.used_slot[w.assoc.slot[i]] = 1;
    w.rep.measurements[i].result = skipped ? Result::kUpdateSkipped : Result::kFused;
  }
  if (skipped) {
    w.rep.update_skipped = true;
    w.result = Status::kNotPositiveDefinite;
    return Status::kOk;
  }
  model_->inject(&w.frame_state, calibration_.stateCorrection(frame_error_.framePoseCorrection(dx)));
  model_->inject(&state_, calibration_.stateCorrection(frame_error_.poseCorrection(dx)));
  book_.correct(dx, backend_->poseDim());
  for (int i : used_meas) book_.observe(w.assoc.slot[i], w.frame->stamp, w.frame->measurements[i].rgb);
  w.rep.n_updated = static_cast<int>(used_meas.size());
  w.rep.mean_nis = nis / w.rep.n_updated;
  // The map an earlier frame built fixes this pose, so the velocity (the
  // displacement since) is measured, unless the pose was just moved to the
  // map fit after an outage with the velocity at rest.
  if (!w.rep.relocalised) velocity_measured_ = true;
  return Status::kOk;
}

// Room for the additions: stale landmarks go when the pool would overflow
// (landmark_book.hpp).
Status Eskf::removeForAdditions(FrameWork& w) {
  const auto t0 = Clock::now();
  w.add_meas = book_.chooseAdditions(w.assoc, w.by_response, settings_);
  const int n_candidates = static_cast<int>(w.add_meas.size());
  const std::vector<int> evict = book_.chooseRemovals(n_candidates, w.used_slot, settings_);
  if (!evict.empty()) {
    const Status st = backend_->removeLandmarks(evict);
    if (st != Status::kOk) {
      w.rep.t_removal_ms = msSince(t0);
      return st;
    }
    book_.remove(evict);  // the same slot plan on the host (removal_plan.hpp)
    w.rep.n_removed = static_cast<int>(evict.size());
  }
  w.n_add = book_.additionsThatFit(n_candidates, settings_);
  w.rep.t_removal_ms = msSince(t0);
  return Status::kOk;
}

Status Eskf::addLandmarks(FrameWork& w) {
  const auto t0 = Clock::now();
  frame_camera_ = model_->camera(w.frame_state);
  const Status st = w.n_add > 0 ? startLandmarks(w) : Status::kOk;
  w.rep.t_addition_ms = msSince(t0);
  return st;
}

// New landmarks from the camera as the frame saw it (frameCamera()).
Status Eskf::startLandmarks(FrameWork& w) {
  const StereoFrame& frame = *w.frame;
  const bool fej = settings_.first_estimate_jacobians;
  const PoseState& camera = frame_camera_;
  // First estimates: the Jacobians at the predicted pose, which also places
  // the landmark's first estimate; the mean from the corrected one.
  const PoseState& camera_lin = fej ? w.camera_predicted : camera;
  const Mat6 J = fej ? w.J_predicted : frameCameraJacobian(w.frame_state);
  std::vector<NewLandmarkBlock> blocks(w.n_add);
  for (int j = 0; j < w.n_add; ++j) {
    const int i = w.add_meas[j];
    const StereoMeasurement& m = frame.measurements[i];
    Mat36 G_camera;
    newLandmarkJacobian(camera_lin, m.z, &G_camera, &blocks[j].G_z);
    blocks[j].G_pose = G_camera * J;
    blocks[j].Cz = m.Cz;
    blocks[j].descriptor =
        frame.descriptor_length > 0 ? &frame.descriptors[static_cast<std::size_t>(i) * frame.descriptor_length]
                                    : nullptr;
  }
  const Status st = backend_->addLandmarks(blocks);
  if (st != Status::kOk) return st;
  for (int j = 0; j < w.n_add; ++j) {
    const int i = w.add_meas[j];
    const StereoMeasurement& m = frame.measurements[i];
    MeasurementOutcome& o = w.rep.measurements[i];
    o.landmark_id = book_.add(initLandmark(camera, m.z), m.rgb, frame.stamp, initLandmark(camera_lin, m.z));
    o.result = MeasurementOutcome::Result::kAdded;
  }
  w.rep.n_added = w.n_add;
  return Status::kOk;
}

bool Eskf::zeroVelocityUsed() const {
  return settings_.zero_velocity_update && model_->usesImu() && !model_->sceneMotion().any();
}

// Before the frame's vision update: the velocity the prediction carries is
// what a still frame contradicts or not (after it, a young landmark's
// correction of the pose would have moved the velocity too, and the gate
// would refuse the zero the frame shows). Not when vision led the frame or
// the scene's motion is a state of its own (the device's velocity is then
// not its velocity relative to the scene).
Status Eskf::updateIfStill(FrameWork& w) {
  if (!zeroVelocityUsed()) return Status::kOk;
  std::vector<StillFrameDetector::Sighting> sightings;
  for (std::size_t i = 0; i < w.frame->measurements.size(); ++i)
    if (w.assoc.slot[i] >= 0) sightings.push_back({book_.ids()[w.assoc.slot[i]], w.frame->measurements[i].z});
  ZeroVelocityStatus& zv = w.rep.zero_velocity;
  zv.still = still_.test(w.frame->stamp, sightings);
  if (!zv.still.still || w.rep.vision_led || w.rep.relocalised) return Status::kOk;
  Eigen::VectorXd dx;
  const Mat3 R_wb = state_.q.toRotationMatrix();
  const auto J = meanVelocityJacobian(model_->kind() == MotionModelKind::kInertial, R_wb, state_.f - state_.b_a,
                                      still_interval_.duration(), model_->poseDim());
  const Status st = zero_velocity_.apply(backend_.get(), still_interval_.meanVelocity(state_.v), J, &zv, &dx);
  if (st != Status::kOk || !zv.fused) return st;
  model_->inject(&state_, calibration_.stateCorrection(frame_error_.poseCorrection(dx)));
  book_.correct(dx, backend_->poseDim());
  return Status::kOk;
}

// The landmarks the frame associated and those it started: the next
// frame's still test compares its own with both (so the second frame
// after a start can be still).
void Eskf::rememberSightings(const FrameWork& w) {
  if (!zeroVelocityUsed()) return;
  std::vector<StillFrameDetector::Sighting> sightings;
  for (const MeasurementOutcome& o : w.rep.measurements)
    if (o.landmark_id != 0 && (o.associated || o.added()))
      sightings.push_back({o.landmark_id, w.frame->measurements[o.measurement].z});
  still_.remember(w.frame->stamp, sightings);
  still_interval_.restart();
}

// Every exit: the frame's backend calls are done, so work the backend
// defers to the time between frames starts here (frameCompleted).
Status Eskf::finishFrame(FrameWork& w, Status s, IterationReport* report) {
  if (backend_) {
    const Status closed = frame_error_.close(backend_.get());
    if (s == Status::kOk) s = closed;
    const Status restored = calibration_.close(backend_.get(), frame_error_);
    if (s == Status::kOk) s = restored;
    const Status deferred = backend_->frameCompleted();
    if (s == Status::kOk) s = deferred;
  }
  w.rep.t_total_ms = msSince(w.start);
  w.rep.n_landmarks = numLandmarks();
  if (report) *report = std::move(w.rep);
  return s;
}

}  // namespace hapi_eskf
