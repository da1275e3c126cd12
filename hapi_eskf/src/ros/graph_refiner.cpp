// ~refine: the batch refinement of the live run (graph_refiner.hpp).
#include "hapi_eskf/ros/graph_refiner.hpp"

#include "hapi_eskf/backend/map_files.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#ifdef HAPI_ESKF_WITH_GRAPH
#include "hapi_eskf/graph/batch_refinement.hpp"
#include "hapi_eskf/graph/eskf_recording.hpp"
#include "hapi_eskf/graph/graph_slam.hpp"
#endif

#include <ros/console.h>

namespace hapi_eskf {
namespace ros_glue {

GraphRefiner::GraphRefiner(const NodeletParams& params, std::string log_name)
    : params_(params), log_name_(std::move(log_name)) {}

GraphRefiner::~GraphRefiner() = default;

void GraphRefiner::attach(SlamBackend* backend) {
  std::lock_guard<std::mutex> lk(mu_);
  eskf_ = nullptr;
  graph_ = nullptr;
#ifdef HAPI_ESKF_WITH_GRAPH
  eskf_ = graph::recordableEskf(backend, params_.filter.backend_algorithm);
  if (eskf_) recorder_ = std::make_unique<graph::EskfRecorder>(params_.filter.graph.keyframe_min_observations);
  graph_ = graph::graphSlamOf(backend);
#else
  (void)backend;
#endif
}

Status GraphRefiner::processFrame(SlamBackend& backend, const StereoFrame& frame, IterationReport* report) {
#ifdef HAPI_ESKF_WITH_GRAPH
  if (eskf_ == &backend) {
    std::lock_guard<std::mutex> lk(mu_);
    return recorder_->processFrame(eskf_, frame, report);
  }
#endif
  return backend.processFrame(frame, report);
}

void GraphRefiner::clear() {
#ifdef HAPI_ESKF_WITH_GRAPH
  std::lock_guard<std::mutex> lk(mu_);
  if (recorder_) recorder_ = std::make_unique<graph::EskfRecorder>(params_.filter.graph.keyframe_min_observations);
#endif
}

bool GraphRefiner::refine(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  res.success = false;
#ifdef HAPI_ESKF_WITH_GRAPH
  graph::GraphMap g;
  {
    std::lock_guard<std::mutex> lk(mu_);
    if (graph_) {
      g = graph_->snapshot();
    } else if (recorder_) {
      g = recorder_->graph();
    } else {
      res.message = std::string("backend_algorithm ") + toString(params_.filter.backend_algorithm) +
                    " has no graph to refine (eskf and graph have)";
      return true;
    }
  }
  if (g.observations.empty()) {
    res.message = "nothing to refine yet (no observations recorded)";
    return true;
  }
  graph::BundleReport rep;
  const Status st = graph::refineBatch(graph::graphSettings(params_.filter), &g, &rep);
  if (st != Status::kOk || !rep.usable) {
    res.message = std::string("refinement failed: ") + toString(st);
    ROS_ERROR_NAMED(log_name_, "~refine: %s", res.message.c_str());
    return true;
  }
  const std::string ply = timestampedPath(params_.output_dir, "hapi_refined_map", "ply");
  const std::string tum = timestampedPath(params_.output_dir, "hapi_refined_trajectory", "tum");
  const std::string err = graph::writeGraphFiles(g, ply, tum);
  res.success = err.empty();
  res.message = res.success ? ply + " " + tum : err;
  if (res.success)
    ROS_INFO_NAMED(log_name_, "~refine: %zu keyframes, %zu landmarks, cost %.1f -> %.1f in %d iterations: %s %s",
                   g.keyframes.size(), g.landmarks.size(), rep.initial_cost, rep.final_cost, rep.iterations,
                   ply.c_str(), tum.c_str());
  else
    ROS_ERROR_NAMED(log_name_, "~refine failed: %s", err.c_str());
#else
  res.message = "Graph SLAM is not built into this hapi_eskf (needs Ceres, libceres-dev)";
#endif
  return true;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
