// FastSLAM 2.0 back end (docs/DESIGN.md "FastSLAM 2.0"): num_particles
// particles (particle.hpp), each stepped with the measurement-driven pose
// proposal, importance weights, and resampling when the effective sample
// size falls below resample_threshold * num_particles. Input: associated
// frames (associated_frame.hpp); a rejected frame leaves the state
// unchanged. Outputs: the weighted mean pose with the particles' spread as
// its covariance, and per landmark the weighted mixture's mean and
// covariance. The per-particle work runs on OpenMP threads when built with
// OpenMP; the draws are seeded per particle and frame, so the result does
// not depend on the thread count.
#pragma once

#include "hapi_eskf/backend/associated_core.hpp"
#include "hapi_eskf/backend/associated_frame.hpp"
#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/fastslam/fastslam_settings.hpp"
#include "hapi_eskf/fastslam/particle.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace hapi_eskf {
namespace fastslam {

struct FastSlamReport {
  int n_known = 0, n_added = 0;
  double effective_sample_size = 0.0;  // before resampling
  bool resampled = false;
};

class FastSlam2 final : public AssociatedCore {
 public:
  explicit FastSlam2(const FastSlamSettings& settings);

  // Every particle at `initial` (exact: it defines the world; its v and w
  // start the constant-velocity prior), no landmarks.
  Status reset(const PoseState& initial, double stamp) override;
  Status processFrame(const AssociatedFrame& frame, FastSlamReport* report = nullptr);
  Status processAssociated(const AssociatedFrame& frame) override { return processFrame(frame); }
  // The mean pose moved by the mean velocity; the spread plus the process noise.
  void predicted(double stamp, PoseState* pose, Mat6* covariance) const override;

  PoseState pose() const override;       // weighted mean (rotation: the weighted Karcher mean)
  Mat6 poseCovariance() const override;  // weighted spread, [dp world, dtheta local] about the mean
  std::vector<LandmarkInfo> landmarks() const override;  // weighted mixture mean and covariance
  // Drops the landmarks from every particle (their slots are refilled from the tail).
  void forget(const std::vector<uint64_t>& ids) override;
  std::size_t memoryBytes() const override;
  bool hasLandmark(uint64_t id) const { return slot_.count(id) > 0; }
  int numLandmarks() const { return static_cast<int>(ids_.size()); }
  const std::vector<Particle>& particles() const { return particles_; }
  std::vector<double> weights() const;  // normalised
  const FastSlamSettings& settings() const { return settings_; }

 private:
  Mat6 processNoise(double dt) const;
  void resample();

  const FastSlamSettings settings_;
  bool initialised_ = false;
  double time_ = 0.0;
  uint64_t frame_count_ = 0;  // seeds the per-particle draws
  std::vector<Particle> particles_;
  std::unordered_map<uint64_t, int> slot_;  // landmark id -> slot (the same in every particle)
  std::vector<uint64_t> ids_;               // slot -> id
  std::vector<std::array<uint8_t, 3>> rgb_;
  std::vector<int> times_observed_;
  std::vector<double> last_seen_;
};

// FastSLAM 2.0's maker (backend/slam_backend_maker.hpp): backend_algorithm
// fastslam2, FastSlam2 behind the shared association and bookkeeping.
std::unique_ptr<SlamBackend> makeFastSlamBackend(const EskfSettings& settings, int descriptor_length,
                                                 const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace fastslam
}  // namespace hapi_eskf
