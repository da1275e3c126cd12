// The error-state EKF over camera pose + landmark pool (docs/DESIGN.md "Filter").
// Host side: nominal state, landmark bookkeeping (ids, positions, colours,
// statistics), Jacobians and association logic. The covariance and the
// descriptors live in a CovarianceBackend (CPU or GPU).
//
// One processFrame() = predict to the frame stamp -> associate (descriptor
// best/second-best + ratio test, then Mahalanobis gate) -> joint update with
// at most max_update_landmarks -> remove (stale landmarks when the pool would
// overflow) -> add at most max_new_landmarks unmatched measurements.
#pragma once

#include "hapi_eskf/covariance_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <vector>

namespace hapi_eskf {

class Eskf {
 public:
  // The backend's capacity must equal settings.max_landmarks.
  Eskf(const EskfSettings& settings, std::unique_ptr<CovarianceBackend> backend);

  // Clears the pool; the pose starts at `initial` with the initial sigmas of
  // the settings. The next frame must have stamp >= `stamp`. The constructor
  // resets to the identity pose at 0; until a reset succeeds (invalid
  // settings, backend capacity != max_landmarks) every other operation
  // returns kNotInitialised (kBackendUnavailable without a backend).
  Status reset(const PoseState& initial, double stamp);

  // Constant-velocity prediction to `stamp` (no-op when stamp == current).
  // kInvalidArgument when stamp is earlier than the filter time.
  Status predictTo(double stamp);

  // Prediction driven by a gyro sample (camera-frame angular rate [rad/s] with
  // its noise density sigma [rad/s/sqrt(Hz)]): w is replaced by the
  // measurement for the step, then the constant-velocity step runs
  // (gyro_prediction.hpp: kNonFinite, kInvalidArgument, state unchanged).
  Status predictWithGyro(double stamp, const Vec3& gyro_camera, double sigma_gyro);

  // One filter iteration. On any input error (kNonFinite, kDuplicateId,
  // kCapacityExceeded, kInvalidArgument, kEmptyInput for a frame without
  // measurements, kNotPositiveDefinite for a non-PD measurement covariance)
  // the state is unchanged. The one exception is a joint innovation covariance
  // S found not PD inside the update: the update is skipped
  // (report->update_skipped), the prediction and bookkeeping still apply, and
  // kNotPositiveDefinite is returned (see src/core/eskf.cpp).
  Status processFrame(const StereoFrame& frame, IterationReport* report = nullptr);

  const PoseState& pose() const { return pose_; }
  double time() const { return time_; }
  Mat12 poseCovariance() const;
  int numLandmarks() const { return static_cast<int>(ids_.size()); }
  std::vector<LandmarkInfo> landmarks() const;  // with marginal covariances
  const std::vector<Vec3>& landmarkPositions() const { return positions_; }
  const std::vector<uint64_t>& landmarkIds() const { return ids_; }
  const EskfSettings& settings() const { return settings_; }
  const CovarianceBackend& backend() const { return *backend_; }
  CovarianceBackend& mutableBackend() { return *backend_; }  // tests and benchmark

 private:
  // Internal steps, exposed to tests through the public API only.
  Status checkFrame(const StereoFrame& frame) const;
  // Re-detection covariance added to C_z (EskfSettings::measurement_angular_sigma).
  Mat3 redetectionCovariance(const Vec3& z) const;

  EskfSettings settings_;
  std::unique_ptr<CovarianceBackend> backend_;
  PoseState pose_;
  double time_ = 0.0;
  bool initialised_ = false;
  // Relocalisation (EskfSettings::relocalise_gap): stamp of the last processed
  // frame, and whether an outage was seen and no map fit has moved the pose yet.
  double last_frame_stamp_ = 0.0, outage_stamp_ = 0.0;
  bool relocalise_pending_ = false;
  uint64_t next_id_ = 1;
  // Per slot, same order as the backend's slots.
  std::vector<uint64_t> ids_;
  std::vector<Vec3> positions_;
  std::vector<std::array<uint8_t, 3>> colours_;
  std::vector<int> times_observed_;
  std::vector<double> last_seen_;
};

}  // namespace hapi_eskf
