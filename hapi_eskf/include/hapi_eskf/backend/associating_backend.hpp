// A SlamBackend (slam_backend.hpp) from an AssociatedCore
// (associated_core.hpp): the back ends without a covariance storage (graph,
// fastslam2) get the filter's association (association.hpp), bookkeeping
// policy (landmark_book.hpp) and descriptor pool (descriptor_pool.hpp)
// here, once, and see only associated frames. docs/DESIGN.md "Graph SLAM",
// "FastSLAM 2.0".
//
// Per frame: check (stereo_frame_check.hpp), re-detection term on C_z, the
// core's predicted pose and covariance, associate (gate marginals: the
// predicted pose covariance and each landmark's own, cross-covariances
// taken as zero), choose updates, removals and additions by the shared
// policy, hand the associated frame to the core; the pool and the book
// change only when the core accepted the frame. Not supported here: IMU
// motion models and relocalisation after an outage (these cores predict
// with constant velocity; a gap only widens their prediction).
#pragma once

#include "hapi_eskf/backend/associated_core.hpp"
#include "hapi_eskf/backend/descriptor_pool.hpp"
#include "hapi_eskf/backend/landmark_book.hpp"
#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"

#include <functional>
#include <memory>
#include <string>

namespace hapi_eskf {

class AssociatingBackend final : public SlamBackend {
 public:
  AssociatingBackend(const EskfSettings& settings, int descriptor_length, std::unique_ptr<AssociatedCore> core);

  const char* name() const override { return toString(settings_.backend_algorithm); }
  // "graph-cpu", "fastslam2-cpu": the diagnostics name the algorithm too.
  std::string storage() const override { return std::string(name()) + "-cpu"; }
  std::size_t memoryBytes() const override;
  Status reset(const PoseState& initial, double stamp) override;
  bool supportsImu() const override { return false; }
  Status setCameraExtrinsic(const CameraExtrinsic& extrinsic) override;
  Status addImu(const ImuSample& sample) override;
  Status predictTo(double stamp) override;
  Status processFrame(const StereoFrame& frame, IterationReport* report = nullptr) override;
  PoseState pose() const override { return core_->pose(); }
  Mat6 cameraPoseCovariance() const override { return core_->poseCovariance(); }
  // The pool's landmarks (the core's estimates).
  std::vector<LandmarkInfo> landmarks() const override;
  int numLandmarks() const override { return book_.size(); }
  double time() const override { return time_; }
  void settle() override { core_->settle(); }

  const AssociatedCore& core() const { return *core_; }

 private:
  const EskfSettings settings_;
  std::unique_ptr<AssociatedCore> core_;
  DescriptorPool pool_;
  LandmarkBook book_;
  bool initialised_ = false;
  double time_ = 0.0;
};

// The maker's part every core on associated frames shares (graph,
// fastslam2): these cores predict with constant velocity only, so another
// motion_model is refused first (nullptr, *error); then makeCore builds the
// core (nullptr with *error when its own settings are invalid), and the back
// end around it starts reset to the identity pose at 0.
std::unique_ptr<SlamBackend> makeAssociatingBackend(
    const EskfSettings& settings, int descriptor_length,
    const std::function<std::unique_ptr<AssociatedCore>(std::string* error)>& makeCore, std::string* error);

// The same for a Core constructed from its own settings table (GraphSettings,
// FastSlamSettings), checked first with their validate().
template <typename Core, typename CoreSettings>
std::unique_ptr<SlamBackend> makeAssociatingBackendOf(const EskfSettings& settings, int descriptor_length,
                                                      const CoreSettings& core_settings, std::string* error) {
  return makeAssociatingBackend(
      settings, descriptor_length,
      [&core_settings](std::string* err) -> std::unique_ptr<AssociatedCore> {
        const std::string bad = core_settings.validate();
        if (!bad.empty()) {
          if (err) *err = bad;
          return nullptr;
        }
        return std::make_unique<Core>(core_settings);
      },
      error);
}

}  // namespace hapi_eskf
