// Graph SLAM back end (docs/DESIGN.md "Graph SLAM"): keyframe poses and
// landmarks of a factor graph of stereo point observations. Per frame, on
// the caller's thread: apply the newest window solution, predict (constant
// velocity), track the pose against the current map (pose_tracker.hpp),
// start new landmarks, and on a keyframe hand the newest window to the
// background solver (window_optimiser.hpp). snapshot() gives the whole graph
// for the full batch refinement (batch_refinement.hpp).
//
// Input: associated frames (associated_frame.hpp); a rejected frame leaves
// the state unchanged. One lock of its own guards the graph and the pose;
// processFrame() holds it for the frame's own work only (never for a solve).
#pragma once

#include "hapi_eskf/backend/associated_core.hpp"
#include "hapi_eskf/backend/associated_frame.hpp"
#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/graph/graph_map.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"
#include "hapi_eskf/graph/window_optimiser.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace graph {

struct GraphFrameReport {
  bool keyframe = false;
  bool tracked = false;        // the pose-only solve ran (else the pose is the prediction)
  int n_known = 0, n_added = 0;
  bool window_applied = false;  // a background solution was merged before this frame
};

class GraphSlam final : public AssociatedCore {
 public:
  // Settings are checked by reset(); until a reset succeeds every frame is
  // kNotInitialised.
  explicit GraphSlam(const GraphSettings& settings);
  ~GraphSlam() override;

  // Empty graph, camera at `initial` (exact: it defines the world) at
  // `stamp`; its v and w (camera frame) start the constant-velocity prediction.
  Status reset(const PoseState& initial, double stamp) override;
  Status processFrame(const AssociatedFrame& frame, GraphFrameReport* report = nullptr);
  Status processAssociated(const AssociatedFrame& frame) override { return processFrame(frame); }
  void predicted(double stamp, PoseState* pose, Mat6* covariance) const override;

  PoseState pose() const override;
  Mat6 poseCovariance() const override;  // [dp world, dtheta local]
  // Every landmark of the graph (also those the pool forgot).
  std::vector<LandmarkInfo> landmarks() const override;
  // The graph keeps forgotten landmarks: the batch refinement uses them.
  void forget(const std::vector<uint64_t>& /*ids*/) override {}
  std::size_t memoryBytes() const override;
  bool hasLandmark(uint64_t id) const;
  int numKeyframes() const;
  // A copy of the whole graph (the batch refinement works on it while the
  // back end carries on).
  GraphMap snapshot() const;
  // Waits for the background solver, then merges its solution (tests,
  // offline replays; before a final read-out).
  void settle() override;
  const GraphSettings& settings() const { return settings_; }

 private:
  void applyWindowResult(const WindowResult& r);  // mutex_ held
  WindowJob makeWindowJob() const;                // mutex_ held
  Mat6 processNoise(double dt) const;
  PoseState predictPose(double stamp) const;  // mutex_ held

  const GraphSettings settings_;
  mutable std::mutex mutex_;
  bool initialised_ = false;
  GraphMap map_;
  // Current camera pose; v (WORLD frame here) and w (camera) from the last two frames.
  PoseState pose_;
  Mat6 pose_cov_ = Mat6::Zero();
  double time_ = 0.0;
  std::unique_ptr<WindowOptimiser> solver_;
};

// The Graph SLAM core behind `backend` (an AssociatingBackend), else nullptr.
const GraphSlam* graphSlamOf(const SlamBackend* backend);

// Graph SLAM's maker (backend/slam_backend_maker.hpp): backend_algorithm
// graph, GraphSlam behind the shared association and bookkeeping.
std::unique_ptr<SlamBackend> makeGraphBackend(const EskfSettings& settings, int descriptor_length,
                                              const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace graph
}  // namespace hapi_eskf
