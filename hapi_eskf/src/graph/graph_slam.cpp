// The Graph SLAM frame loop (graph_slam.hpp). Policies (docs/DESIGN.md
// "Graph SLAM"):
//  * every frame that starts landmarks is a keyframe (a landmark must have
//    an observation in the graph), as is a frame keyframe_translation or
//    keyframe_rotation away from the last keyframe;
//  * observations of non-keyframes are used for tracking only;
//  * the window: the newest window_keyframes keyframes move, every landmark
//    they observe moves, every other keyframe observing those landmarks is
//    held fixed in the solve (no marginalisation prior), keyframe 0 always
//    (gauge); for the window's covariances the fixed keyframes stand for
//    their own marginal covariances (bundle_adjustment.hpp).
#include "hapi_eskf/graph/graph_slam.hpp"

#include "hapi_eskf/backend/associating_backend.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/graph/pose_tracker.hpp"
#include "hapi_eskf/so3.hpp"

#include <algorithm>
#include <unordered_map>

namespace hapi_eskf {
namespace graph {

GraphSlam::GraphSlam(const GraphSettings& settings) : settings_(settings) {}

const GraphSlam* graphSlamOf(const SlamBackend* backend) {
  const auto* a = dynamic_cast<const AssociatingBackend*>(backend);
  return a ? dynamic_cast<const GraphSlam*>(&a->core()) : nullptr;
}

GraphSlam::~GraphSlam() = default;

Status GraphSlam::reset(const PoseState& initial, double stamp) {
  if (!settings_.validate().empty()) return Status::kInvalidArgument;
  if (!std::isfinite(stamp) || !initial.p.allFinite() || !initial.q.coeffs().allFinite()) return Status::kNonFinite;
  if (initial.q.norm() < 1e-6) return Status::kInvalidArgument;
  if (solver_) solver_->waitIdle();
  std::lock_guard<std::mutex> lock(mutex_);
  solver_ = std::make_unique<WindowOptimiser>(settings_);  // drops any old solution
  map_ = GraphMap();
  pose_ = PoseState();
  pose_.p = initial.p;
  pose_.q = initial.q.normalized();
  pose_.v = pose_.q * initial.v;  // the prediction's velocity is kept in the world frame
  pose_.w = initial.w;
  pose_cov_.setZero();
  time_ = stamp;
  initialised_ = true;
  return Status::kOk;
}

Mat6 GraphSlam::processNoise(double dt) const {
  return poseRandomWalkNoise(dt, settings_.sigma_acceleration, settings_.sigma_angular_acceleration);
}

Status GraphSlam::processFrame(const AssociatedFrame& frame, GraphFrameReport* report) {
  GraphFrameReport rep;
  std::optional<WindowResult> solved = solver_ ? solver_->takeResult() : std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!initialised_) return Status::kNotInitialised;
  const Status st = checkAssociatedFrame(frame, time_, [this](uint64_t id) { return map_.landmarks.count(id) > 0; });
  if (st != Status::kOk) {
    // A solution is still worth merging; the frame changes nothing.
    if (solved) applyWindowResult(*solved);
    return st;
  }
  if (solved) {
    applyWindowResult(*solved);
    rep.window_applied = true;
  }

  // Predict with constant velocity (docs/DESIGN.md "Graph SLAM", tracking).
  const double dt = frame.stamp - time_;
  const PoseState predicted = predictPose(frame.stamp);
  Mat6 cov = pose_cov_ + processNoise(dt);

  std::vector<TrackedPoint> points;
  for (const AssociatedMeasurement& m : frame.measurements) {
    if (m.is_new) continue;
    const GraphLandmark& l = map_.landmarks.at(m.landmark_id);
    points.push_back(TrackedPoint{l.position, l.covariance, m.z, m.Cz});
  }
  rep.n_known = static_cast<int>(points.size());
  PoseState x = predicted;
  if (rep.n_known >= settings_.tracking_min_landmarks) {
    Mat6 C;
    if (trackPose(points, predicted, settings_, &x, &C)) {
      // C is the pose given the landmarks, each with its own error; what they
      // share does not average away over them: the window's placement in the
      // world (the newest keyframe's marginal stands for it) and the frame's
      // own shared vision error Sigma_f (camera frame; dp is in the world
      // here) (docs/DESIGN.md "Graph SLAM", covariances).
      Mat6 J = Mat6::Identity();
      J.topLeftCorner<3, 3>() = x.q.toRotationMatrix();
      cov = C + (map_.keyframes.empty() ? Mat6::Zero() : map_.keyframes.back().covariance) +
            J * settings_.frame_error_covariance * J.transpose();
      rep.tracked = true;
    }
  }
  if (dt > 0.0) {
    x.v = (x.p - pose_.p) / dt;
    x.w = logSO3(pose_.q.toRotationMatrix().transpose() * x.q.toRotationMatrix()) / dt;
  }

  // Keyframe?
  const bool adds = std::any_of(frame.measurements.begin(), frame.measurements.end(),
                                [](const AssociatedMeasurement& m) { return m.is_new; });
  bool keyframe = adds || map_.keyframes.empty();
  if (!keyframe) {
    const Keyframe& k = map_.keyframes.back();
    keyframe = (x.p - k.p).norm() > settings_.keyframe_translation ||
               k.q.angularDistance(x.q) > settings_.keyframe_rotation;
  }
  if (keyframe) {
    const int kf = map_.addKeyframe(frame.stamp, x.p, x.q);
    if (kf > 0) map_.keyframes[kf].covariance = cov;  // keyframe 0 is the gauge: exact
    for (const AssociatedMeasurement& m : frame.measurements) {
      if (m.is_new) {
        // m = p + R z with the pose's and the measurement's covariance
        // (docs/DESIGN.md "New landmark").
        GraphLandmark l;
        Mat36 G_pose;
        Mat3 G_z;
        newLandmarkJacobian(x, m.z, &G_pose, &G_z);
        l.position = initLandmark(x, m.z);
        l.covariance = G_z * m.Cz * G_z.transpose() + G_pose * cov * G_pose.transpose();
        l.covariance = (0.5 * (l.covariance + l.covariance.transpose())).eval();
        map_.landmarks.emplace(m.landmark_id, l);
        ++rep.n_added;
      }
      map_.addObservation(kf, m.landmark_id, m.z, m.Cz);
    }
  }
  for (const AssociatedMeasurement& m : frame.measurements) {
    GraphLandmark& l = map_.landmarks.at(m.landmark_id);
    l.last_seen = frame.stamp;
    l.rgb = m.rgb;
  }
  // The frame relative to the newest keyframe, so refinements move it along.
  FramePose f;
  f.stamp = frame.stamp;
  f.keyframe = static_cast<int>(map_.keyframes.size()) - 1;
  const Keyframe& ref = map_.keyframes.back();
  f.q_rel = (ref.q.conjugate() * x.q).normalized();
  f.p_rel = ref.q.conjugate() * (x.p - ref.p);
  map_.frames.push_back(f);

  pose_ = x;
  pose_cov_ = cov;
  time_ = frame.stamp;
  rep.keyframe = keyframe;
  if (keyframe && map_.keyframes.size() >= 2) solver_->submit(makeWindowJob());
  if (report) *report = rep;
  return Status::kOk;
}

PoseState GraphSlam::predictPose(double stamp) const {
  const double dt = stamp - time_;
  PoseState x = pose_;
  x.p = pose_.p + pose_.v * dt;
  x.q = (pose_.q * quatExp(pose_.w * dt)).normalized();
  return x;
}

void GraphSlam::predicted(double stamp, PoseState* pose, Mat6* covariance) const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseState x = predictPose(stamp);
  x.v = x.q.conjugate() * pose_.v;  // types.hpp: v in the camera frame
  *pose = x;
  *covariance = pose_cov_ + processNoise(std::max(0.0, stamp - time_));
}

std::size_t GraphSlam::memoryBytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return map_.keyframes.size() * sizeof(Keyframe) + map_.observations.size() * (sizeof(Observation) + 2 * sizeof(int)) +
         map_.landmarks.size() * (sizeof(GraphLandmark) + sizeof(uint64_t)) + map_.frames.size() * sizeof(FramePose);
}

WindowJob GraphSlam::makeWindowJob() const {
  const int n = static_cast<int>(map_.keyframes.size());
  const int first_free = std::max(1, n - settings_.window_keyframes);
  WindowJob job;
  std::unordered_map<int, int> local;  // global keyframe -> local
  auto localKeyframe = [&](int g) {
    const auto it = local.find(g);
    if (it != local.end()) return it->second;
    const Keyframe& k = map_.keyframes[g];
    const int l = job.map.addKeyframe(k.stamp, k.p, k.q);
    job.map.keyframes[l].covariance = k.covariance;
    job.constant.push_back(g < first_free);
    job.keyframe_index.push_back(g);
    local.emplace(g, l);
    return l;
  };
  for (int g = first_free; g < n; ++g) localKeyframe(g);
  for (int g = first_free; g < n; ++g)
    for (int oi : map_.keyframes[g].observations) {
      const uint64_t id = map_.observations[oi].landmark;
      if (job.map.landmarks.count(id)) continue;
      const GraphLandmark& src = map_.landmarks.at(id);
      GraphLandmark& dst = job.map.landmarks[id];
      dst.position = src.position;
      dst.covariance = src.covariance;
      for (int oj : src.observations) {
        const Observation& o = map_.observations[oj];
        job.map.addObservation(localKeyframe(o.keyframe), id, o.z, o.Cz);
      }
    }
  return job;
}

void GraphSlam::applyWindowResult(const WindowResult& r) {
  const WindowJob& w = r.solved;
  for (std::size_t l = 0; l < w.keyframe_index.size(); ++l) {
    if (w.constant[l]) continue;
    Keyframe& k = map_.keyframes[w.keyframe_index[l]];
    k.p = w.map.keyframes[l].p;
    k.q = w.map.keyframes[l].q;
    k.covariance = w.map.keyframes[l].covariance;
  }
  for (const auto& kv : w.map.landmarks) {
    GraphLandmark& l = map_.landmarks.at(kv.first);
    l.position = kv.second.position;
    l.covariance = kv.second.covariance;
  }
}

PoseState GraphSlam::pose() const {
  std::lock_guard<std::mutex> lock(mutex_);
  PoseState x = pose_;
  x.v = x.q.conjugate() * pose_.v;  // types.hpp: v in the camera frame
  return x;
}

Mat6 GraphSlam::poseCovariance() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pose_cov_;
}

std::vector<LandmarkInfo> GraphSlam::landmarks() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<LandmarkInfo> out;
  out.reserve(map_.landmarks.size());
  for (const auto& kv : map_.landmarks) {
    LandmarkInfo i;
    i.id = kv.first;
    i.position = kv.second.position;
    i.covariance = kv.second.covariance;
    i.rgb = kv.second.rgb;
    i.times_observed = static_cast<int>(kv.second.observations.size());
    i.last_seen = kv.second.last_seen;
    out.push_back(i);
  }
  std::sort(out.begin(), out.end(), [](const LandmarkInfo& a, const LandmarkInfo& b) { return a.id < b.id; });
  return out;
}

bool GraphSlam::hasLandmark(uint64_t id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return map_.landmarks.count(id) > 0;
}

int GraphSlam::numKeyframes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(map_.keyframes.size());
}

GraphMap GraphSlam::snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return map_;
}

void GraphSlam::settle() {
  if (!solver_) return;
  solver_->waitIdle();
  std::optional<WindowResult> r = solver_->takeResult();
  std::lock_guard<std::mutex> lock(mutex_);
  if (r) applyWindowResult(*r);
}

}  // namespace graph
}  // namespace hapi_eskf
