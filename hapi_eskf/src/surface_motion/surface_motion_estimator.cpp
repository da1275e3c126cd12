#include "hapi_eskf/surface_motion/surface_motion_estimator.hpp"

#include "hapi_eskf/so3.hpp"
#include "hapi_eskf/surface_motion/rts_smoother.hpp"

#include <algorithm>
#include <utility>

namespace hapi_eskf {
namespace surface_motion {

namespace {
// Flows held for the odometry at most (the odometry runs ahead of the
// flow by the camera's latency; more means the odometry stopped).
constexpr std::size_t kMaxPending = 8;
}  // namespace

const char* toString(FlowOutcome o) {
  switch (o) {
    case FlowOutcome::kFused: return "fused";
    case FlowOutcome::kGated: return "gated";
    case FlowOutcome::kPending: return "pending";
    case FlowOutcome::kOutOfOrder: return "out of order";
    case FlowOutcome::kInvalid: return "invalid";
    case FlowOutcome::kTooOld: return "too old";
    case FlowOutcome::kNoGeometry: return "no geometry";
    case FlowOutcome::kNoCamera: return "no camera";
    case FlowOutcome::kNoPose: return "no pose";
  }
  return "?";
}

SurfaceMotionEstimator::SurfaceMotionEstimator(const SurfaceMotionSettings& s) : s_(s), filter_(s) {}

std::string SurfaceMotionEstimator::setCamera(const ImagingCamera& cam) {
  std::string why = cam.check();
  if (!why.empty()) return why;
  cam_ = cam;
  has_camera_ = true;
  return "";
}

void SurfaceMotionEstimator::setMap(std::vector<Vec3> landmarks_world) { map_ = std::move(landmarks_world); }

void SurfaceMotionEstimator::reset() {
  odom_.clear();
  filter_ = RelativeVelocityFilter(s_);
  contexts_.clear();
  pending_.clear();
  pending_outcomes_.clear();
  last_flow_t_.reset();
  last_fused_t_.reset();
  fused_since_output_ = false;
}

SurfaceMotionOutput SurfaceMotionEstimator::statusOutput(double t, MotionStatus st, std::string message) const {
  SurfaceMotionOutput out;
  out.t = t;
  out.status = st;
  out.message = std::move(message);
  if (has_camera_) {
    const Vec2 p = pixel();
    out.u = p.x();
    out.v = p.y();
    out.frame_rate = cam_.frame_rate;
  } else {
    out.u = s_.pixel_u;
    out.v = s_.pixel_v;
  }
  return out;
}

Eigen::Isometry3d SurfaceMotionEstimator::poseAt(double t) const {
  // odom_ is sorted by t and covers t (the caller checks).
  auto it = std::lower_bound(odom_.begin(), odom_.end(), t,
                             [](const CameraOdometry& o, double x) { return o.t < x; });
  if (it == odom_.begin()) return it->T_world_cam;
  return interpolatePose(*(it - 1), *it, t);
}

template <typename F>
void SurfaceMotionEstimator::forEachOdometryInterval(double t0, double t1, F&& f) const {
  auto first = std::lower_bound(odom_.begin(), odom_.end(), t0,
                                [](const CameraOdometry& o, double x) { return o.t < x; });
  const std::size_t k0 = std::max<std::size_t>(1, static_cast<std::size_t>(first - odom_.begin()));
  for (std::size_t k = k0; k < odom_.size() && odom_[k - 1].t < t1; ++k) {
    const double a = std::max(odom_[k - 1].t, t0), b = std::min(odom_[k].t, t1);
    if (b > a) f(odom_[k - 1], odom_[k], b - a);
  }
}

Eigen::Isometry3d SurfaceMotionEstimator::motionBetween(double t0, double t1) const {
  // Each odometry interval [t_k-1, t_k] moves the camera by the mean of its
  // two twists; the part of it inside [t0, t1] is taken. The poses
  // themselves jump where the filter corrects them (each frame), the twist
  // only by the velocity's correction.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  forEachOdometryInterval(t0, t1, [&](const CameraOdometry& o0, const CameraOdometry& o1, double h) {
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.linear() = expSO3(0.5 * (o0.w + o1.w) * h);
    step.translation() = 0.5 * (o0.v + o1.v) * h;
    T = T * step;
  });
  return T;
}

bool SurfaceMotionEstimator::meanTwist(double t0, double t1, Vec3* v, Vec3* w) const {
  Vec3 sv = Vec3::Zero(), sw = Vec3::Zero();
  double covered = 0;
  forEachOdometryInterval(t0, t1, [&](const CameraOdometry& o0, const CameraOdometry& o1, double h) {
    sv += 0.5 * (o0.v + o1.v) * h;
    sw += 0.5 * (o0.w + o1.w) * h;
    covered += h;
  });
  if (covered <= 0) return false;
  *v = sv / covered;
  *w = sw / covered;
  return true;
}

std::optional<SurfaceMotionOutput> SurfaceMotionEstimator::addOdometry(const CameraOdometry& odom) {
  pending_outcomes_.clear();
  if (!odom.valid() || (!odom_.empty() && odom.t <= odom_.back().t)) return std::nullopt;
  if (!filter_.started()) {
    filter_.start(odom.t);
  } else {
    const Mat3 R_new_old = odom.T_world_cam.linear().transpose() * odom_.back().T_world_cam.linear();
    filter_.predict(odom.t, R_new_old);
  }
  odom_.push_back(odom);
  while (odom_.size() > 2 && odom_.back().t - odom_.front().t > s_.history_length) odom_.pop_front();

  // Held flows whose interval the odometry now covers, oldest first.
  while (!pending_.empty() && pending_.front().t <= odom.t) {
    const FlowMeasurement f = pending_.front();
    pending_.pop_front();
    pending_outcomes_.push_back(fuse(f, nullptr));
  }

  Context c{odom.t, MotionStatus::kOk, "", odom.v, odom.w, RayGeometry(), fused_since_output_};
  if (s_.twist_average_window > 0) meanTwist(odom.t - s_.twist_average_window, odom.t, &c.v, &c.w);
  fused_since_output_ = false;
  if (!has_camera_) {
    c.status = MotionStatus::kNoExtrinsic;
    c.message = "no camera model of the imaging camera (CameraInfo) yet";
  } else {
    const RaySurface rs = surfaceAtRay(map_, odom.T_world_cam, cam_, cam_.ray(pixel()), s_);
    c.status = rs.status;
    c.message = rs.message;
    c.geometry = rs.geometry;
  }
  contexts_.push_back(c);
  while (!contexts_.empty() && contexts_.front().t < filter_.steps().front().t) contexts_.pop_front();
  return makeOutput(c, filter_.e(), filter_.covariance());
}

std::optional<SurfaceMotionOutput> SurfaceMotionEstimator::outputWithNewFlows() {
  if (!fused_since_output_ || contexts_.empty()) return std::nullopt;
  fused_since_output_ = false;
  Context& c = contexts_.back();
  c.flow_fused = true;
  return makeOutput(c, filter_.e(), filter_.covariance());
}

SurfaceMotionOutput SurfaceMotionEstimator::makeOutput(const Context& c, const Vec3& e, const Mat3& P) const {
  SurfaceMotionOutput out = statusOutput(c.t, c.status, c.message);
  out.flow_fused = c.flow_fused;
  if (c.status != MotionStatus::kOk) return out;
  // The twist's own uncertainty is not added: e is the velocity the
  // odometry does not explain, its error included (DESIGN "Surface motion").
  MapInputCovariance Cq = MapInputCovariance::Zero();
  Cq.block<3, 3>(6, 6) = P;
  Cq.block<4, 4>(9, 9) = c.geometry.covariance;
  out.velocity = mapVelocity(mapInput(c.v, c.w, e, c.geometry), Cq, c.geometry.ray, cam_);
  return out;
}

FlowOutcome SurfaceMotionEstimator::addFlow(const FlowMeasurement& f, std::string* why) {
  std::string reason = checkFlow(f, s_.min_flow_interval, s_.max_flow_interval);
  FlowOutcome o = FlowOutcome::kFused;
  const double last = pending_.empty() ? last_flow_t_.value_or(-1e300) : pending_.back().t;
  if (!reason.empty()) {
    o = FlowOutcome::kInvalid;
  } else if (f.t <= last) {
    o = FlowOutcome::kOutOfOrder;
    reason = "stamp " + std::to_string(f.t) + " not after the previous flow's " + std::to_string(last);
  } else if (!filter_.started()) {
    o = FlowOutcome::kNoPose;
    reason = "no odometry yet";
  } else if (f.t > odom_.back().t) {
    if (pending_.size() == kMaxPending) pending_.pop_front();
    pending_.push_back(f);
    o = FlowOutcome::kPending;
  } else {
    return fuse(f, why);
  }
  if (why != nullptr) *why = reason;
  return o;
}

FlowOutcome SurfaceMotionEstimator::fuse(const FlowMeasurement& f, std::string* why) {
  last_flow_t_ = f.t;
  auto fail = [&](FlowOutcome o, std::string reason) {
    if (why != nullptr) *why = std::move(reason);
    return o;
  };
  if (!has_camera_) return fail(FlowOutcome::kNoCamera, "no camera model of the imaging camera yet");
  if (f.t_prev < odom_.front().t) return fail(FlowOutcome::kTooOld, "its interval starts before the odometry kept");
  const Eigen::Isometry3d T0 = poseAt(f.t_prev), T1 = poseAt(f.t);
  const Vec3 ray = cam_.ray(Vec2(f.u, f.v));
  const RaySurface rs = surfaceAtRay(map_, T0, cam_, ray, s_);
  if (rs.status != MotionStatus::kOk) return fail(FlowOutcome::kNoGeometry, rs.message);
  // The flow measures the mean of e over [t_prev, t] (times dt). It updates
  // the stored step nearest its middle (the filter predicts the later steps
  // again); for a random walk the mean differs from e there by noise of
  // variance q^2 dt / 12, added to the measurement's (DESIGN "Surface
  // motion", fusion). e_k is in the camera frame at t_k: R_c1_ck e_k at t.
  const double dt = f.t - f.t_prev;
  const std::size_t k = filter_.stepFor(0.5 * (f.t_prev + f.t));
  const FilterStep& st = filter_.steps()[k];
  const Mat3 R_c1_ck = T1.linear().transpose() * poseAt(st.t).linear();
  const FlowPrediction p = predictFlow(rs.geometry, motionBetween(f.t_prev, f.t).inverse(), R_c1_ck * st.e, dt, cam_);
  const Mat23 H = p.H * R_c1_ck;
  const Mat3 lag = filter_.processNoise(dt / 12 + std::abs(0.5 * (f.t_prev + f.t) - st.t));
  const Mat2 R = f.displacementCovariance() + p.R_geometry + H * lag * H.transpose();
  const UpdateResult u = filter_.update(k, f.displacement() - p.displacement, H, R);
  if (u.fused) {
    fused_since_output_ = true;
    last_fused_t_ = f.t;
    return FlowOutcome::kFused;
  }
  return fail(FlowOutcome::kGated, "innovation NIS " + std::to_string(u.nis) + " beyond the gate");
}

SurfaceMotionEstimator::Context SurfaceMotionEstimator::smoothedTwist(std::size_t i) const {
  // A centred quadratic Savitzky-Golay fit over 9 odometry samples (45 ms at
  // 200 Hz): it passes a 12 Hz tremor with 2.4 % loss and quarters the
  // variance of the gyro's white noise in w, which the causal output carries
  // in full (DESIGN "Surface motion", smoother). Near the ends: as given.
  static constexpr double kWeights[9] = {-21, 14, 39, 54, 59, 54, 39, 14, -21};
  static constexpr int kHalf = 4;
  Context c = contexts_[i];
  if (i < kHalf || i + kHalf >= contexts_.size()) return c;
  c.v.setZero();
  c.w.setZero();
  for (int k = -kHalf; k <= kHalf; ++k) {
    c.v += kWeights[k + kHalf] / 231.0 * contexts_[i + k].v;
    c.w += kWeights[k + kHalf] / 231.0 * contexts_[i + k].w;
  }
  return c;
}

std::vector<SurfaceMotionOutput> SurfaceMotionEstimator::smoothed(double start, double end) const {
  std::vector<SurfaceMotionOutput> out;
  for (const SmoothedState& st : smoothInterval(filter_.steps(), start, end)) {
    auto it = std::lower_bound(contexts_.begin(), contexts_.end(), st.t,
                               [](const Context& c, double x) { return c.t < x; });
    if (it == contexts_.end() || it->t != st.t) continue;
    out.push_back(makeOutput(smoothedTwist(static_cast<std::size_t>(it - contexts_.begin())), st.e, st.P));
  }
  return out;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
