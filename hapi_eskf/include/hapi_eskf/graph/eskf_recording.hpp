// The ES-EKF's run recorded as a factor graph (docs/DESIGN.md "Graph SLAM",
// refinement of the filter's stream): every processed frame becomes a
// keyframe at the filter's pose, every measurement the filter used in its
// update or started a landmark with becomes an observation of that landmark
// (with the C_z the filter used, re-detection term included), and each
// landmark keeps the filter's latest estimate as its initial value. The full
// batch refinement (batch_refinement.hpp) then re-linearises all of it.
//
// The filter does not hand out its per-measurement association, so the
// recorder recomputes it with the filter's own association function on the
// predicted state, exactly as the filter's iteration does, and checks it
// against the filter's bookkeeping (which landmarks were updated, which
// started): a frame where the two disagree (after an outage the filter
// relocalises first) keeps only the observations both agree on and is
// counted in mismatchedFrames().
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

  // One filter iteration on `eskf` (predictTo + processFrame: the same
  // result as processFrame alone), recorded. Returns the filter's status;
  // frames the filter rejects or holds back (relocalising) are not recorded.
  Status processFrame(Eskf* eskf, const StereoFrame& frame, IterationReport* report = nullptr);

  const GraphMap& graph() const { return graph_; }
  int mismatchedFrames() const { return mismatched_frames_; }

 private:
  const int min_observations_;
  GraphMap graph_;
  int mismatched_frames_ = 0;
};

}  // namespace graph
}  // namespace hapi_eskf
