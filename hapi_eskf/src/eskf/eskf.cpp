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

}  // namespace

Eskf::Eskf(const EskfSettings& settings, std::unique_ptr<CovarianceBackend> backend,
           const CameraExtrinsic& extrinsic)
    : settings_(settings),
      backend_(std::move(backend)),
      model_(makeMotionModel(settings, extrinsic)),
      frame_error_(model_->poseDim(), settings),
      scene_motion_(settings),
      relocaliser_(settings) {
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
  scene_motion_.reset();
  initialised_ = true;
  book_.clear();
  return Status::kOk;
}

Status Eskf::setCameraExtrinsic(const CameraExtrinsic& extrinsic) {
  if (!extrinsic.R_imu_cam.allFinite() || !extrinsic.p_imu_cam.allFinite()) return Status::kNonFinite;
  if (!isRotation(extrinsic.R_imu_cam)) return Status::kInvalidArgument;
  const PoseState camera = pose();
  model_ = makeMotionModel(settings_, extrinsic);
  model_->moveCameraTo(&state_, camera.p, camera.q);
  restartFirstEstimates();
  return Status::kOk;
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
  if (st == Status::kOk) advanceFirstEstimates();
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
  const Status st = predictStepTo(stamp, nullptr);
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
    alignment_samples_.push_back(sample);
    if (sample.stamp - alignment_samples_.front().stamp >= settings_.alignment_window) return align();
    return Status::kOk;
  }
  const Status st = predictStepTo(sample.stamp, &sample);
  if (st == Status::kOk) scene_motion_.addImu(sample, state_.b_g);
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
  clearPendingPrediction();
  state_ = start.x;
  restartFirstEstimates();
  time_ = alignment_samples_.back().stamp;
  relocaliser_.reset(time_);
  for (const ImuSample& m : alignment_samples_) scene_motion_.addImu(m, state_.b_g);
  alignment_samples_.clear();
  awaiting_alignment_ = false;
  velocity_measured_ = start.window.still;  // zero, measured by the still window
  return Status::kOk;
}

PoseMat Eskf::poseCovariance() const {
  if (!backend_) return PoseMat::Zero(model_->poseDim(), model_->poseDim());
  const PoseMat C = frame_error_.modelBlock(backend_->poseCovariance());
  return pending_steps_ ? predictPoseCovariance(C, pending_F_, pending_Q_) : C;
}

Mat12 Eskf::cameraCovariance() const { return hapi_eskf::cameraCovariance(*model_, state_, poseCovariance()); }

std::vector<LandmarkInfo> Eskf::landmarks() const {
  if (!backend_) return book_.info({});
  return book_.info(backend_->landmarkCovariances());
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

Status Eskf::checkFrame(const StereoFrame& frame) const {
  return checkStereoFrame(frame, time_, backend_->descriptorLength(), settings_.max_frame_measurements);
}

Mat3 Eskf::redetectionCovariance(const Vec3& z) const {
  return hapi_eskf::redetectionCovariance(z, settings_.measurement_angular_sigma);
}

Status Eskf::processFrame(const StereoFrame& frame_in, IterationReport* report) {
  const auto t_start = Clock::now();
  IterationReport rep;
  rep.n_measurements = static_cast<int>(frame_in.measurements.size());
  rep.n_landmarks = numLandmarks();
  // Every exit: the frame's backend calls are done, so work the backend
  // defers to the time between frames starts here (frameCompleted).
  auto finish = [&](Status s) {
    if (backend_) {
      const Status closed = frame_error_.close(backend_.get());
      if (s == Status::kOk) s = closed;
      const Status deferred = backend_->frameCompleted();
      if (s == Status::kOk) s = deferred;
    }
    rep.t_total_ms = msSince(t_start);
    rep.n_landmarks = numLandmarks();
    if (report) *report = rep;
    return s;
  };
  if (!backend_) return finish(Status::kBackendUnavailable);
  if (!initialised_) return finish(Status::kNotInitialised);
  if (awaiting_alignment_) return finish(Status::kAwaitingImu);
  // Everything that can be wrong with the input is found here, before any change.
  Status st = checkFrame(frame_in);
  if (st != Status::kOk) return finish(st);
  // Measurement model: C_z of the stereo pair plus the keypoint's re-detection
  // noise across frames (settings.hpp, measurement_angular_sigma), used for
  // gating, the update and new landmarks alike.
  StereoFrame inflated;
  if (settings_.measurement_angular_sigma > 0.0) {
    inflated = frame_in;
    for (StereoMeasurement& m : inflated.measurements) m.Cz += redetectionCovariance(m.z);
  }
  const StereoFrame& frame = settings_.measurement_angular_sigma > 0.0 ? inflated : frame_in;

  // --- predict ---
  // After an outage longer than relocalise_gap the last velocity says nothing
  // about the motion since: predict from rest (settings.hpp).
  const NominalState state_before = state_, lin_before = lin_;
  const bool velocity_measured_before = velocity_measured_;
  if (relocaliser_.beginFrame(frame.stamp)) {
    model_->stop(&state_);
    restartFirstEstimates();
    velocity_measured_ = false;
  }
  auto t0 = Clock::now();
  st = predictStepTo(frame.stamp, nullptr);
  if (st == Status::kOk) st = flushPrediction();
  rep.t_predict_ms = msSince(t0);
  if (st != Status::kOk) {
    state_ = state_before;  // a rejected frame changes nothing
    lin_ = lin_before;
    relocaliser_.rollback();
    velocity_measured_ = velocity_measured_before;
    return finish(st);
  }
  const double previous_frame_stamp = relocaliser_.acceptFrame(frame.stamp);
  // From here to finish() the first 6 pose columns are the pose this frame
  // sees, with its shared vision error (frame_error_block.hpp).
  st = frame_error_.open(backend_.get(), model_->cameraJacobian(state_));
  if (st != Status::kOk) return finish(st);

  // --- association ---
  t0 = Clock::now();
  Association assoc;
  st = associate(frame, pose(), model_->cameraJacobian(state_), book_.positions(), *backend_, settings_, &assoc);
  const bool have_fit = st == Status::kOk && assoc.fit_inliers >= kRelocaliseMinInliers;
  // IMU and vision agreement (models with IMU; scene_motion_monitor.hpp).
  bool vision_leads = false;
  if (have_fit && model_->usesImu() && !relocaliser_.pending()) {
    const SceneMotionVerdict v = scene_motion_.onFrame(assoc.fit_inliers, assoc.n_fit_inliers_gated_out);
    vision_leads = v.disagreed;
    rep.vision_led = v.disagreed;
    rep.scene_moving = v.disagreed && v.device_still;
    // A moving device whose prediction vision contradicts: the motion states
    // (velocity, biases, gravity) are what is wrong (a start in a fast turn
    // levels the map by a mean acceleration, the velocity starts at rest):
    // their uncertainty goes back to the prior, so this frame's update and
    // the next ones estimate them afresh instead of keeping a wrong,
    // confident value that disagrees frame after frame.
    if (v.disagreed && !v.device_still) {
      const int P = model_->poseDim();
      st = backend_->predict(frame_error_.transition(PoseMat::Identity(P, P)),
                             frame_error_.noise(model_->motionStatesPrior()));
      if (st != Status::kOk) return finish(st);
    }
  }
  if (have_fit && (relocaliser_.pending() || vision_leads)) {
    // The map fit becomes the linearisation point (means only), then gate
    // again around it. After an outage the velocity was set to rest; when
    // vision leads, the velocity mean takes the displacement the prediction
    // missed over this frame interval, so the next prediction starts from a
    // velocity vision supports (left alone, a wrong velocity makes every
    // following frame disagree again).
    if (vision_leads && !relocaliser_.pending() && frame.stamp > previous_frame_stamp)
      model_->correctVelocity(&state_, assoc.fit_t - pose().p, frame.stamp - previous_frame_stamp);
    model_->moveCameraTo(&state_, assoc.fit_t, Eigen::Quaterniond(assoc.fit_R).normalized());
    restartFirstEstimates();
    rep.relocalised = relocaliser_.fitApplied();
    st = associate(frame, pose(), model_->cameraJacobian(state_), book_.positions(), *backend_, settings_, &assoc);
  }
  rep.t_association_ms = msSince(t0);
  if (st != Status::kOk) return finish(st);
  rep.n_candidates = assoc.n_candidates;
  rep.n_gated_out = assoc.n_gated_out;
  if (relocaliser_.holdFrame(frame.stamp)) {
    rep.relocalising = true;  // settings.hpp kRelocaliseWaitS: wait for a frame the map supports
    return finish(Status::kOk);
  }

  const std::vector<int> by_response = LandmarkBook::byResponse(frame);

  // --- update ---
  t0 = Clock::now();
  Status result = Status::kOk;
  const std::vector<int> used_meas = LandmarkBook::chooseUpdates(assoc, by_response, settings_);
  std::vector<char> used_slot(numLandmarks(), 0);
  // The frame's predicted camera pose and its Jacobian: the update's
  // linearisation point, and with first-estimate Jacobians also the new
  // landmarks' (docs/DESIGN.md "First-estimate Jacobians").
  const bool fej = settings_.first_estimate_jacobians;
  const PoseState camera_predicted = pose();
  const Mat6 J_predicted = model_->cameraJacobian(state_);
  // The state the frame saw: new landmarks are placed from it (with a
  // modelled frame error it differs from the corrected state by the
  // estimate of that error).
  NominalState frame_state = state_;
  if (!used_meas.empty()) {
    const PoseState& camera = camera_predicted;
    const Mat6& J = J_predicted;
    const std::vector<Vec3>& lin_positions = fej ? book_.firstEstimates() : book_.positions();
    std::vector<MeasurementBlock> blocks(used_meas.size());
    for (std::size_t j = 0; j < used_meas.size(); ++j) {
      const int i = used_meas[j], k = assoc.slot[i];
      MeasurementBlock& b = blocks[j];
      b.slot = k;
      Mat36 H_camera;
      measurementJacobian(camera, lin_positions[k], &H_camera, &b.H_landmark);
      b.H_pose = H_camera * J;
      b.R = frame.measurements[i].Cz;
      b.innovation = frame.measurements[i].z - measure(camera, book_.positions()[k]);
    }
    Eigen::VectorXd dx;
    double nis = 0.0;
    st = backend_->update(blocks, &dx, &nis);
    if (st == Status::kOk) {
      model_->inject(&frame_state, frame_error_.framePoseCorrection(dx));
      model_->inject(&state_, frame_error_.poseCorrection(dx));
      book_.correct(dx, backend_->poseDim());
      for (int i : used_meas) {
        const int k = assoc.slot[i];
        used_slot[k] = 1;
        book_.observe(k, frame.stamp, frame.measurements[i].rgb);
      }
      rep.n_updated = static_cast<int>(used_meas.size());
      rep.mean_nis = nis / rep.n_updated;
      // The map an earlier frame built fixes this pose, so the velocity
      // (the displacement since) is measured, unless the pose was just
      // moved to the map fit after an outage with the velocity at rest.
      if (!rep.relocalised) velocity_measured_ = true;
    } else if (st == Status::kNotPositiveDefinite || st == Status::kNonFinite) {
      rep.update_skipped = true;
      result = Status::kNotPositiveDefinite;
      // The landmarks were still associated: protect them from eviction.
      for (int i : used_meas) used_slot[assoc.slot[i]] = 1;
    } else {
      rep.t_update_ms = msSince(t0);
      return finish(st);
    }
  }
  rep.t_update_ms = msSince(t0);

  // --- removal ---
  t0 = Clock::now();
  const std::vector<int> add_meas = book_.chooseAdditions(assoc, by_response, settings_);
  const int n_candidates = static_cast<int>(add_meas.size());
  const std::vector<int> evict = book_.chooseRemovals(n_candidates, used_slot, settings_);
  if (!evict.empty()) {
    st = backend_->removeLandmarks(evict);
    if (st != Status::kOk) {
      rep.t_removal_ms = msSince(t0);
      return finish(st);
    }
    book_.remove(evict);  // the same slot plan on the host (removal_plan.hpp)
    rep.n_removed = static_cast<int>(evict.size());
  }
  const int n_add = book_.additionsThatFit(n_candidates, settings_);
  rep.t_removal_ms = msSince(t0);

  // --- addition ---
  t0 = Clock::now();
  frame_camera_ = model_->camera(frame_state);
  const PoseState& camera = frame_camera_;
  if (n_add > 0) {
    // First estimates: the Jacobians at the predicted pose, which also
    // places the landmark's first estimate; the mean from the corrected one.
    const PoseState& camera_lin = fej ? camera_predicted : camera;
    const Mat6 J = fej ? J_predicted : model_->cameraJacobian(frame_state);
    std::vector<NewLandmarkBlock> blocks(n_add);
    for (int j = 0; j < n_add; ++j) {
      const int i = add_meas[j];
      const StereoMeasurement& m = frame.measurements[i];
      Mat36 G_camera;
      newLandmarkJacobian(camera_lin, m.z, &G_camera, &blocks[j].G_z);
      blocks[j].G_pose = G_camera * J;
      blocks[j].Cz = m.Cz;
      blocks[j].descriptor =
          frame.descriptor_length > 0 ? &frame.descriptors[static_cast<std::size_t>(i) * frame.descriptor_length]
                                      : nullptr;
    }
    st = backend_->addLandmarks(blocks);
    if (st != Status::kOk) {
      rep.t_addition_ms = msSince(t0);
      return finish(st);
    }
    for (int j = 0; j < n_add; ++j) {
      const StereoMeasurement& m = frame.measurements[add_meas[j]];
      book_.add(initLandmark(camera, m.z), m.rgb, frame.stamp, initLandmark(camera_lin, m.z));
    }
    rep.n_added = n_add;
  }
  rep.t_addition_ms = msSince(t0);
  return finish(result);
}

}  // namespace hapi_eskf
