#include "surface_motion_statistics.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

namespace hapi_eskf {
namespace ros_glue {

using surface_motion::FlowOutcome;
using surface_motion::MotionStatus;

void SurfaceMotionStatistics::countOutput(MotionStatus s) {
  ++outputs;
  switch (s) {
    case MotionStatus::kOk: ++outputs_ok; break;
    case MotionStatus::kNoPose: ++no_pose; break;
    case MotionStatus::kNoDepth: ++no_depth; break;
    case MotionStatus::kRayMissesMap: ++ray_misses_map; break;
    case MotionStatus::kNoExtrinsic: ++missing_extrinsic; break;
  }
}

void SurfaceMotionStatistics::countFlow(FlowOutcome o) {
  switch (o) {
    case FlowOutcome::kFused: ++flows_fused; break;
    case FlowOutcome::kGated: ++flows_gated; break;
    case FlowOutcome::kPending: break;
    case FlowOutcome::kOutOfOrder: ++flows_out_of_order; break;
    case FlowOutcome::kInvalid: ++flows_invalid; break;
    case FlowOutcome::kTooOld: ++flows_too_old; break;
    case FlowOutcome::kNoGeometry: ++flows_no_geometry; break;
    case FlowOutcome::kNoCamera: ++missing_extrinsic; break;
    case FlowOutcome::kNoPose: ++flows_before_pose; break;
  }
}

void SurfaceMotionStatistics::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const std::uint64_t flows = flows_received, fused = flows_fused, outs = outputs, ok = outputs_ok;
  const bool flows_came = flows > last_flows_, none_fused = fused == last_fused_;
  const bool outs_came = outs > last_outputs_, none_ok = ok == last_ok_;
  if (missing_extrinsic > 0 && outs_came && none_ok)
    stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no extrinsic or no CameraInfo of the imaging camera");
  else if (outs_came && none_ok)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no output OK in the last period (no depth at the pixel?)");
  else if (flows_came && none_fused)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "flows arrive but none was fused in the last period");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
  last_flows_ = flows;
  last_fused_ = fused;
  last_outputs_ = outs;
  last_ok_ = ok;
  const std::pair<const char*, const Counter*> keys[] = {
      {"odom received", &odom_received},         {"odom rejected", &odom_rejected},
      {"time jumps (reset)", &time_jumps},       {"outputs", &outputs},
      {"outputs ok", &outputs_ok},               {"no pose outputs", &no_pose},
      {"no depth outputs", &no_depth},           {"ray misses map outputs", &ray_misses_map},
      {"missing extrinsic", &missing_extrinsic}, {"flows received", &flows_received},
      {"flows fused", &flows_fused},             {"flows gated", &flows_gated},
      {"flows out of order", &flows_out_of_order}, {"flows invalid", &flows_invalid},
      {"flows wrong frame", &flows_wrong_frame}, {"flows too old", &flows_too_old},
      {"flows without depth", &flows_no_geometry}, {"flows before odometry", &flows_before_pose},
      {"maps received", &maps_received},         {"maps rejected", &maps_rejected},
      {"camera_info rejected", &camera_info_rejected}, {"smoothed_motion requests", &smoothed_requests}};
  for (const auto& k : keys) stat.add(k.first, static_cast<unsigned long long>(k.second->load()));
  const hapi_nodelet_kit::LatencyHistogram::Summary lat = flow_latency.summary();
  stat.add("flow_latency_p50_ms", lat.p50 * 1e3);
  stat.add("flow_latency_p99_ms", lat.p99 * 1e3);
  stat.add("flow_latency_max_ms", lat.max * 1e3);
  stat.add("flow_latency_samples", static_cast<unsigned long long>(lat.count));
}

}  // namespace ros_glue
}  // namespace hapi_eskf
