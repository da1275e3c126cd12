// The back-end interface (docs/DESIGN.md "Back ends"): what the nodelet, the
// replay tools and the comparison harness see of a SLAM back end, whatever
// its algorithm (backend_algorithm: eskf | seif | graph | fastslam2).
//
// Every back end takes the same input (StereoFrame, IMU samples where its
// motion model uses them) and gives the same outputs (camera pose with its
// covariance, the landmark map with a 3x3 covariance per point). What they
// share is not repeated inside them: descriptor association, RANSAC fit and
// Mahalanobis gate (association.hpp, over an AssociationSource), the
// bookkeeping policy (landmark_book.hpp) and relocalisation after an outage
// (relocaliser.hpp).
//
// Contract common to every implementation: a call that returns anything but
// kOk leaves the state unchanged (the one documented exception is a
// processFrame whose joint update fails after the prediction: see eskf.hpp);
// no call throws on bad input.
#pragma once

#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace hapi_eskf {

// The pose-block state an IMU-rate output continues from (defined with the
// motion models, eskf/motion_model.hpp): back ends whose motion model
// predicts with the IMU give it through poseBlockState().
struct PoseBlockState;

class SlamBackend {
 public:
  virtual ~SlamBackend() = default;

  // The backend_algorithm value ("eskf", "seif", ...).
  virtual const char* name() const = 0;
  // Where its state lives, for diagnostics ("cpu", "cuda", "seif-cpu", ...).
  virtual std::string storage() const = 0;
  virtual std::size_t memoryBytes() const = 0;
  // The device call behind the last Status::kBackendError ("" when none or
  // the storage has no device).
  virtual std::string lastError() const { return {}; }

  // Empties the map; the camera starts at `initial` (camera pose in the world)
  // at `stamp`. Until a reset succeeds every other call returns kNotInitialised.
  virtual Status reset(const PoseState& initial, double stamp) = 0;

  // IMU input. supportsImu(): whether this back end with its settings uses
  // IMU samples (motion_model gyro or inertial); addImu() returns
  // kInvalidArgument when it does not.
  virtual bool supportsImu() const = 0;
  virtual Status setCameraExtrinsic(const CameraExtrinsic& extrinsic) = 0;
  virtual Status addImu(const ImuSample& sample) = 0;

  // Motion prediction to `stamp` without a frame (a frame without landmarks).
  virtual Status predictTo(double stamp) = 0;

  // One frame: predict, associate, update, remove, add. kAwaitingImu while an
  // inertial start still collects its gravity window.
  virtual Status processFrame(const StereoFrame& frame, IterationReport* report = nullptr) = 0;

  // The left camera: pose in the world and camera-frame velocities (zero
  // where the algorithm has none).
  virtual PoseState pose() const = 0;
  // Covariance of the camera pose in [dp, dtheta] (6 x 6, world position,
  // rotation error on the right as everywhere in the filter: q = q_hat Exp(dtheta)).
  virtual Mat6 cameraPoseCovariance() const = 0;
  // [dp, dtheta, dv, dw] (12 x 12). Default: the pose block and an
  // uninformative twist block (kUnknownTwistVariance on its diagonal) for
  // algorithms without velocity states.
  virtual Mat12 cameraCovariance() const;
  // The map: per landmark id, position, 3x3 marginal covariance, colour,
  // times observed, last seen.
  virtual std::vector<LandmarkInfo> landmarks() const = 0;
  virtual int numLandmarks() const = 0;
  virtual double time() const = 0;  // stamp of the state [s]

  // Waits for the work this back end does off the caller's thread (graph's
  // window solve) and merges its result. Live, that work runs beside the
  // frames; an offline replay (compare_backends) calls this after each frame
  // so that its figures do not depend on how fast the machine replays.
  // Default: nothing runs in the background.
  virtual void settle() {}

  // IMU-rate output: the pose-block state to propagate from (false: this
  // back end has none, no IMU-rate output).
  virtual bool poseBlockState(PoseBlockState* /*out*/) const { return false; }

  static constexpr double kUnknownTwistVariance = 1e6;
};

}  // namespace hapi_eskf
