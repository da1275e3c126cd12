// Recording of an ES-EKF run as a factor graph (eskf_recording.hpp).
#include "hapi_eskf/graph/eskf_recording.hpp"

#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"

#include <unordered_map>

namespace hapi_eskf {
namespace graph {

Eskf* recordableEskf(SlamBackend* backend, BackendAlgorithm algorithm) {
  return algorithm == BackendAlgorithm::kEskf ? dynamic_cast<Eskf*>(backend) : nullptr;
}

Status EskfRecorder::processFrame(Eskf* eskf, const StereoFrame& frame, IterationReport* report) {
  IterationReport rep;
  std::unordered_map<uint64_t, int> seen_before;  // id -> times observed
  for (const LandmarkInfo& l : eskf->landmarks()) seen_before.emplace(l.id, l.times_observed);
  const std::vector<uint64_t> ids_before = eskf->landmarkIds();

  // The filter's C_z (settings.hpp measurement_angular_sigma) for gating and the graph alike.
  StereoFrame inflated = frame;
  for (StereoMeasurement& m : inflated.measurements)
    m.Cz += redetectionCovariance(m.z, eskf->settings().measurement_angular_sigma);
  // The association the iteration will compute: its prediction first (the
  // iteration's own prediction is then a step of length 0).
  Association assoc;
  bool have_assoc = false;
  if (std::isfinite(frame.stamp) && frame.stamp >= eskf->time() && !frame.measurements.empty() &&
      eskf->predictTo(frame.stamp) == Status::kOk)
    have_assoc = associate(inflated, eskf->pose(), eskf->motionModel().cameraJacobian(eskf->state()),
                           eskf->landmarkPositions(), eskf->backend(), eskf->settings(), &assoc) == Status::kOk;

  const Status st = eskf->processFrame(frame, &rep);
  if (report) *report = rep;
  if ((st != Status::kOk && st != Status::kNotPositiveDefinite) || rep.relocalising) return st;

  const PoseState pose = eskf->pose();
  const std::vector<LandmarkInfo> after = eskf->landmarks();
  std::unordered_map<uint64_t, const LandmarkInfo*> now;
  for (const LandmarkInfo& l : after) now.emplace(l.id, &l);

  int used = 0, matched = 0;
  for (const LandmarkInfo& l : after) {
    const auto b = seen_before.find(l.id);
    if (b != seen_before.end() && l.times_observed > b->second) ++used;
  }
  const int n = static_cast<int>(frame.measurements.size());
  std::vector<std::pair<int, uint64_t>> observed;  // (measurement, landmark)
  for (int i = 0; i < n; ++i) {
    const StereoMeasurement& m = inflated.measurements[i];
    uint64_t id = 0;
    if (have_assoc && assoc.slot[i] >= 0) {
      // Updated in this frame: its observation count went up.
      const uint64_t a = ids_before[assoc.slot[i]];
      const auto it = now.find(a);
      if (it != now.end() && it->second->times_observed > seen_before.at(a)) {
        id = a;
        ++matched;
      }
    } else {
      // Started by this measurement: a new id at exactly m = p + R z, from
      // the camera as the frame saw it.
      const Vec3 x = initLandmark(eskf->frameCamera(), m.z);
      for (const LandmarkInfo& l : after)
        if (!seen_before.count(l.id) && (l.position - x).norm() <= 1e-9 * (1.0 + x.norm())) {
          id = l.id;
          break;
        }
    }
    if (id != 0) observed.emplace_back(i, id);
  }
  if (static_cast<int>(observed.size()) >= min_observations_ || graph_.keyframes.empty()) {
    const int kf = graph_.addKeyframe(frame.stamp, pose.p, pose.q);
    graph_.frames.push_back(FramePose{frame.stamp, kf, Vec3::Zero(), Eigen::Quaterniond::Identity()});
    for (const auto& o : observed) {
      const StereoMeasurement& m = inflated.measurements[o.first];
      graph_.landmarks[o.second].rgb = m.rgb;
      graph_.addObservation(kf, o.second, m.z, m.Cz);
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
    for (const auto& o : observed) graph_.landmarks[o.second].rgb = inflated.measurements[o.first].rgb;
  }
  if (matched != used) ++mismatched_frames_;
  // The filter's latest estimates are the graph's initial values.
  for (const LandmarkInfo& l : after) {
    const auto it = graph_.landmarks.find(l.id);
    if (it == graph_.landmarks.end()) continue;
    it->second.position = l.position;
    it->second.covariance = l.covariance;
    it->second.last_seen = l.last_seen;
  }
  return st;
}

}  // namespace graph
}  // namespace hapi_eskf
