// Recording of an ES-EKF run as a factor graph (eskf_recording.hpp).
#include "hapi_eskf/graph/eskf_recording.hpp"

#include <utility>
#include <vector>

namespace hapi_eskf {
namespace graph {

Eskf* recordableEskf(SlamBackend* backend, BackendAlgorithm algorithm) {
  return algorithm == BackendAlgorithm::kEskf ? dynamic_cast<Eskf*>(backend) : nullptr;
}

Status EskfRecorder::processFrame(Eskf* eskf, const StereoFrame& frame, IterationReport* report) {
  IterationReport rep;
  const Status st = eskf->processFrame(frame, &rep);
  // Recorded: every frame the filter processed, a skipped update included.
  const bool processed = st == Status::kOk || (st == Status::kNotPositiveDefinite && rep.update_skipped);
  if (processed && !rep.relocalising) record(*eskf, frame, rep);
  if (report) *report = std::move(rep);
  return st;
}

void EskfRecorder::record(const Eskf& eskf, const StereoFrame& frame, const IterationReport& rep) {
  // The measurements the filter fused or started a landmark with, in frame order.
  std::vector<const MeasurementOutcome*> observed;
  int fused = 0, added = 0;
  for (const MeasurementOutcome& o : rep.measurements) {
    fused += o.fused();
    added += o.added();
    if (o.fused() || o.added()) observed.push_back(&o);
  }
  if (fused != rep.n_updated || added != rep.n_added) ++mismatched_frames_;
  const PoseState pose = eskf.pose();
  if (static_cast<int>(observed.size()) >= min_observations_ || graph_.keyframes.empty()) {
    const int kf = graph_.addKeyframe(frame.stamp, pose.p, pose.q);
    graph_.frames.push_back(FramePose{frame.stamp, kf, Vec3::Zero(), Eigen::Quaterniond::Identity()});
    for (const MeasurementOutcome* o : observed) {
      const StereoMeasurement& m = frame.measurements[o->measurement];
      graph_.landmarks[o->landmark_id].rgb = m.rgb;
      graph_.addObservation(kf, o->landmark_id, m.z, o->Cz);
    }
  } else {
    // Weakly observed: the frame rides on the previous keyframe.
    const Keyframe& ref = graph_.keyframes.back();
    FramePose f;
    f.stamp = frame.stamp;
    f.keyframe = static_cast<int>(graph_.keyframes.size()) - 1;
    f.q_rel = (ref.q.conjugate() * pose.q).normalized();
    f.p_rel = ref.q.conjugate() * (pose.p - ref.p);
    graph_.frames.push_back(f);
    for (const MeasurementOutcome* o : observed)
      graph_.landmarks[o->landmark_id].rgb = frame.measurements[o->measurement].rgb;
  }
  // The filter's latest estimates are the graph's initial values.
  for (const LandmarkInfo& l : eskf.landmarks()) {
    const auto it = graph_.landmarks.find(l.id);
    if (it == graph_.landmarks.end()) continue;
    it->second.position = l.position;
    it->second.covariance = l.covariance;
    it->second.last_seen = l.last_seen;
  }
}

}  // namespace graph
}  // namespace hapi_eskf
