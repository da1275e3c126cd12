// The surface-motion estimator (docs/DESIGN.md "Surface motion"): the
// imaging camera's IMU-rate odometry, the map and the image flow in; the
// skin's motion at the measurement pixel out at every odometry sample, and
// the smoothed motion over a past interval. ROS-free; the nodelet
// (SurfaceMotionNodelet) and surface_motion_replay drive it alike.
//
// Order of inputs: odometry with increasing stamps; flows with increasing
// stamps, each fused as soon as the odometry covers its interval (held until
// then); the map whenever a new snapshot comes.
#pragma once

#include "hapi_eskf/surface_motion/camera_odometry.hpp"
#include "hapi_eskf/surface_motion/flow_measurement.hpp"
#include "hapi_eskf/surface_motion/ray_surface.hpp"
#include "hapi_eskf/surface_motion/relative_velocity_filter.hpp"

#include <deque>
#include <optional>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace surface_motion {

// One output: the message's content (SurfaceMotion.msg).
struct SurfaceMotionOutput {
  double t = 0;
  MotionStatus status = MotionStatus::kNoPose;
  std::string message;  // why, when not OK
  double u = 0, v = 0, frame_rate = 0;
  SurfaceVelocity velocity;  // valid when status is OK
  bool flow_fused = false;
};

// What became of one flow measurement.
enum class FlowOutcome {
  kFused,
  kGated,       // its innovation failed the chi-square gate
  kPending,     // held until the odometry reaches its stamp
  kOutOfOrder,  // its stamp is not after the previous flow's
  kInvalid,     // checkFlow failed
  kTooOld,      // its interval starts before the odometry kept
  kNoGeometry,  // no depth at the flow's pixel at t_prev (status in *why)
  kNoCamera,    // no imaging camera model yet
  kNoPose,      // no odometry yet
};
const char* toString(FlowOutcome o);

class SurfaceMotionEstimator {
 public:
  explicit SurfaceMotionEstimator(const SurfaceMotionSettings& s);

  // "" when accepted (ImagingCamera::check).
  std::string setCamera(const ImagingCamera& cam);
  bool hasCamera() const { return has_camera_; }
  const ImagingCamera& camera() const { return cam_; }
  // The measurement pixel (the settings' pixel_u/v; -1 = centre).
  Vec2 pixel() const { return cam_.pixel(s_.pixel_u, s_.pixel_v); }

  void setMap(std::vector<Vec3> landmarks_world);
  std::size_t mapSize() const { return map_.size(); }

  // The imaging camera's odometry (extrinsic applied: toRigidlyAttached).
  // Empty when its stamp is not after the previous one or it is not valid().
  std::optional<SurfaceMotionOutput> addOdometry(const CameraOdometry& odom);
  // A flow; flows held for the odometry are fused by a later addOdometry
  // (pendingOutcomes() reports them). *why: the reason when not fused.
  FlowOutcome addFlow(const FlowMeasurement& f, std::string* why = nullptr);
  // Outcomes of held flows decided by the last addOdometry.
  const std::vector<FlowOutcome>& pendingOutcomes() const { return pending_outcomes_; }
  // The output at the newest odometry instant again, with the flows fused
  // since its first output (flow_fused); empty when none was fused or there
  // is no odometry. A flow that arrives after the odometry covered its
  // stamp is fused at once: this output carries it without waiting for the
  // next odometry sample (up to one IMU period of latency less).
  std::optional<SurfaceMotionOutput> outputWithNewFlows();
  // Stamp of the newest flow fused (its later frame's), if any: the output
  // that first carries it (flow_fused) measures the flow's latency.
  std::optional<double> lastFusedFlowStamp() const { return last_fused_t_; }

  // The outputs at the stored odometry instants in [start, end], recomputed
  // with the smoothed e (rts_smoother.hpp).
  std::vector<SurfaceMotionOutput> smoothed(double start, double end) const;

  // Forget odometry, flows and filter (the camera and the map stay).
  void reset();

  // An output carrying only a status (no pose, no extrinsic) at t.
  SurfaceMotionOutput statusOutput(double t, MotionStatus st, std::string message) const;

 private:
  struct Context {  // what an output was computed from, for the smoother
    double t;
    MotionStatus status;
    std::string message;
    Vec3 v, w;
    RayGeometry geometry;
    bool flow_fused;
  };
  FlowOutcome fuse(const FlowMeasurement& f, std::string* why);
  // contexts_[i] with its twist smoothed over its neighbours (the smoother's outputs).
  Context smoothedTwist(std::size_t i) const;
  Eigen::Isometry3d poseAt(double t) const;
  // The camera's motion over [t0, t1] (T_c0_c1) from the odometry's twist,
  // integrated (docs/DESIGN.md "Surface motion", fusion).
  Eigen::Isometry3d motionBetween(double t0, double t1) const;
  // f(sample k-1, sample k, h) for each odometry interval overlapping
  // [t0, t1], h the length of the overlap (> 0), oldest first.
  template <typename F>
  void forEachOdometryInterval(double t0, double t1, F&& f) const;
  // The odometry's twist (v, w) averaged over [t0, t1] (trapezoid; over the
  // part the kept odometry covers); false when it covers none of it.
  bool meanTwist(double t0, double t1, Vec3* v, Vec3* w) const;
  SurfaceMotionOutput makeOutput(const Context& c, const Vec3& e, const Mat3& P) const;

  SurfaceMotionSettings s_;
  ImagingCamera cam_;
  bool has_camera_ = false;
  std::vector<Vec3> map_;
  std::deque<CameraOdometry> odom_;
  RelativeVelocityFilter filter_;
  std::deque<Context> contexts_;
  std::deque<FlowMeasurement> pending_;
  std::vector<FlowOutcome> pending_outcomes_;
  std::optional<double> last_flow_t_, last_fused_t_;
  bool fused_since_output_ = false;
};

}  // namespace surface_motion
}  // namespace hapi_eskf
