// Counters of hapi_eskf/SurfaceMotionNodelet and its /diagnostics status.
// Atomics: counted from any callback thread without a lock.
#pragma once

#include "hapi_eskf/surface_motion/surface_motion_estimator.hpp"

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <hapi_nodelet_kit/latency_histogram.hpp>

#include <atomic>
#include <cstdint>

namespace hapi_eskf {
namespace ros_glue {

struct SurfaceMotionStatistics {
  using Counter = std::atomic<std::uint64_t>;
  Counter odom_received{0}, odom_rejected{0}, time_jumps{0};
  Counter outputs{0}, outputs_ok{0}, no_pose{0}, no_depth{0}, ray_misses_map{0}, missing_extrinsic{0};
  Counter flows_received{0}, flows_fused{0}, flows_gated{0}, flows_out_of_order{0}, flows_invalid{0},
      flows_wrong_frame{0}, flows_too_old{0}, flows_no_geometry{0}, flows_before_pose{0};
  Counter maps_received{0}, maps_rejected{0}, camera_info_rejected{0};
  Counter smoothed_requests{0};
  // The imaging frame's stamp (mid-exposure) to the first output carrying
  // its flow, over the run (ROS clock: the bag's in a replay).
  hapi_nodelet_kit::LatencyHistogram flow_latency;  // its own lock

  // One output's status.
  void countOutput(surface_motion::MotionStatus s);
  // One flow's outcome (kPending is counted when it is decided).
  void countFlow(surface_motion::FlowOutcome o);

  // WARN when flows come but none is fused, or no output is OK; ERROR when
  // there is no extrinsic; else OK. Every counter as a key.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  std::uint64_t last_flows_ = 0, last_fused_ = 0, last_outputs_ = 0, last_ok_ = 0;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
