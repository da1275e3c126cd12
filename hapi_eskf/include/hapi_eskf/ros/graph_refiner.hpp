// ~refine of hapi_eskf/EskfNodelet (docs/DESIGN.md "Graph SLAM", batch
// refinement): the full batch refinement of the run so far, written as
// hapi_refined_map_<UTC>.ply and hapi_refined_trajectory_<UTC>.tum into
// ~output_dir (the formats of ~save_map / ~save_trajectory, in the filter's
// world frame). Its graph: the graph back end's own (GraphSlam::snapshot),
// or, when the ES-EKF is the live back end, the filter's run recorded as a
// graph frame by frame (eskf_recording.hpp) while it runs. Other back ends
// (seif, fastslam2) have nothing to refine: the service says so.
//
// Threads: the worker calls processFrame() / clear() / attach(); the service
// runs in a ROS callback thread, copies the graph under mu_ and refines the
// copy there, so the worker never waits for a refinement. The recorded
// graph grows with the run (every filter observation is kept).
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/ros/params.hpp"

#include <std_srvs/Trigger.h>

#include <memory>
#include <mutex>
#include <string>

namespace hapi_eskf {
class Eskf;
namespace graph {
class EskfRecorder;
class GraphSlam;
}  // namespace graph

namespace ros_glue {

class GraphRefiner {
 public:
  GraphRefiner(const NodeletParams& params, std::string log_name);
  ~GraphRefiner();

  // --- worker thread ---
  // The back end the worker created (once): where the graph comes from.
  void attach(SlamBackend* backend);
  // backend.processFrame(), recorded when the ES-EKF is the back end.
  Status processFrame(SlamBackend& backend, const StereoFrame& frame, IterationReport* report);
  void clear();  // the filter was reset

  // --- ~refine service ---
  bool refine(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);

 private:
  const NodeletParams params_;
  const std::string log_name_;
  std::mutex mu_;  // guards the pointers and the recorder
  Eskf* eskf_ = nullptr;                     // the recorded back end, or
  const graph::GraphSlam* graph_ = nullptr;  // the graph back end's core
  std::unique_ptr<graph::EskfRecorder> recorder_;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
