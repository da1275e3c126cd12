// Private (~) parameters of StereoFrontendNodelet: read with strict type
// checks and validated once at start-up. The nodelet refuses to run on any
// invalid value (a silently defaulted typo would make a robot run with a
// configuration nobody asked for). Defaults and meaning: config/frontend.yaml.
#pragma once

#include "hapi_frontend/stereo_pipeline.hpp"

#include <ros/node_handle.h>

#include <string>
#include <vector>

namespace hapi_frontend {

struct FrontendNodeletParams {
  PipelineParams pipeline;            // detector, N, matching, MMSE noise ...
  bool approximate_sync = false;      // false: exact stamps (one camera trigger)
  int queue_size = 5;                 // per-topic synchroniser / subscriber queue
  double approx_slop = 0.005;         // [s] max |t_left - t_right| accepted in approximate mode
  std::string image_transport = "raw";  // raw | compressed | ... (image_transport plugin)
  int mono16_bits = 16;               // significant bits of mono16 input (12-bit cameras: 12)
  double max_backwards_jump = 1.0;    // [s] a larger backwards stamp jump is a time reset (bag loop)
};

struct ParamLoadResult {
  std::vector<std::string> errors;    // each one makes the nodelet refuse to run
  std::vector<std::string> warnings;  // e.g. unknown parameter names (typos)
  bool ok() const { return errors.empty(); }
};

// Reads every parameter from the private node handle (missing ones keep the
// defaults of FrontendNodeletParams/PipelineParams) and validates all of them.
ParamLoadResult loadFrontendParams(const ros::NodeHandle& private_nh, FrontendNodeletParams* params);

// The parameter names this nodelet understands (relative to ~).
const std::vector<std::string>& frontendParamNames();

}  // namespace hapi_frontend
