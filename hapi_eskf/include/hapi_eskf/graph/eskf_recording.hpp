// The ES-EKF's run recorded as a factor graph (docs/DESIGN.md "Graph SLAM",
// refinement of the filter's stream): every processed frame becomes a
// keyframe at the filter's pose, every measurement the filter used in its
// update or started a landmark with becomes an observation of that landmark
// (with the C_z the filter used, re-detection term included), and each
// landmark keeps the filter's latest estimate as its initial value. The full
// batch refinement (batch_refinement.hpp) then re-linearises all of it.
//
// The filter reports what it did with each measurement of a frame
// (IterationReport::measurements: fused into which landmark, or started
// which one, with the C_z it used); the recorder takes those outcomes as
// they are.
#pragma once

#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/graph/graph_map.hpp"
#include "hapi_eskf/status.hpp"

namespace hapi_eskf {
namespace graph {

// The ES-EKF behind `backend` when its run can be recorded, else nullptr:
// the ES-EKF itself, not the SEIF that runs on its host logic (the
// algorithm tells the two apart).
Eskf* recordableEskf(SlamBackend* backend, BackendAlgorithm algorithm);

class EskfRecorder {
 public:
  // Frames with fewer than `min_keyframe_observations` observations are kept
  // relative to the previous keyframe and their observations left out
  // (GraphSettings::keyframe_min_observations).
  explicit EskfRecorder(int min_keyframe_observations) : min_observations_(min_keyframe_observations) {}

  // One filter iteration on `eskf` (its processFrame), recorded. Returns
  // the filter's status; frames the filter rejects or holds back
  // (relocalising) are not recorded.
  Status processFrame(Eskf* eskf, const StereoFrame& frame, IterationReport* report = nullptr);

  const GraphMap& graph() const { return graph_; }
  // Recorded frames whose outcomes disagree with the report's own counts
  // (n_updated, n_added): a check of the filter's bookkeeping, 0 when sound.
  int mismatchedFrames() const { return mismatched_frames_; }

 private:
  void record(const Eskf& eskf, const StereoFrame& frame, const IterationReport& rep);

  const int min_observations_;
  GraphMap graph_;
  int mismatched_frames_ = 0;
};

}  // namespace graph
}  // namespace hapi_eskf
