// Private (~) parameters of StereoFrontendNodelet, read once at start-up with
// hapi_nodelet_kit::ParamReader (typed reads, misspelled names, renamed
// parameters). The ranges are declared once, next to the fields:
// PipelineParams::visit() for the pipeline, FrontendNodeletParams::visit()
// for the nodelet's own, hapi_nodelet_kit for ~time_jump_reset. Any violation
// makes the nodelet refuse to run (hapi_nodelet_kit::StartupFailure).
// Values and meaning for users: config/frontend.yaml.
#pragma once

#include "hapi_frontend/param_spec.hpp"
#include "frontend_self_check.hpp"
#include "hapi_frontend/stereo_pipeline.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>
#include <hapi_nodelet_kit/stamp_guard.hpp>

#include <string>

namespace hapi_frontend {

struct FrontendNodeletParams {
  PipelineParams pipeline;            // detector, N, matching, MMSE noise ...
  bool approximate_sync = false;      // false: exact stamps (one camera trigger)
  int queue_size = 5;                 // per-topic synchroniser / subscriber queue
  double approx_slop = 0.005;         // [s] max |t_left - t_right| accepted in approximate mode
  std::string image_transport = "raw";  // raw | compressed | ... (image_transport plugin)
  int mono16_bits = 16;               // significant bits of mono16 input (12-bit cameras: 12)
  SelfCheckThresholds self_check;     // check_*: the self-checks' thresholds
  // [s] StampGuard: a stamp further back than this is a time jump (bag loop).
  double time_jump_reset = hapi_nodelet_kit::TimeJumpResetParam::kDefault;

  // The nodelet's own fields (not the pipeline's, not time_jump_reset) with
  // their declarations.
  void visit(ParamVisitor& v);
};

// The deprecated name of ~time_jump_reset in this nodelet.
constexpr const char* kOldTimeJumpResetName = "max_backwards_jump";

// Reads every parameter through `reader` into *params (unset ones keep their
// defaults) and validates all of them; every problem lands in `reader`
// (errors: wrong type, out of range; warnings: deprecated or unknown names).
void readFrontendParams(hapi_nodelet_kit::ParamReader& reader, FrontendNodeletParams* params);

}  // namespace hapi_frontend
