// Private (~) parameters of ImagingFlowNodelet, read once at start-up: the
// tracker's (ImageFlowParams::visit(), hapi_frontend/image_flow_params.hpp)
// and the nodelet's own (below). Any violation makes the nodelet refuse to
// run (hapi_nodelet_kit::StartupFailure). Users' reference: docs/RUNNING.md
// "Image flow of the imaging camera".
#pragma once

#include "hapi_frontend/image_flow_params.hpp"
#include "hapi_frontend/param_spec.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>

#include <string>

namespace hapi_frontend {

struct ImagingFlowNodeletParams {
  ImageFlowParams flow;
  std::string image_transport = "raw";  // raw | compressed | ... (image_transport plugin)
  int mono16_bits = 16;                 // significant bits of mono16 input

  // The nodelet's own fields with their declarations.
  void visit(ParamVisitor& v);
};

// Reads every parameter through `reader` into *params (unset ones keep their
// defaults) and validates all of them; every problem lands in `reader`.
void readImagingFlowParams(hapi_nodelet_kit::ParamReader& reader, ImagingFlowNodeletParams* params);

}  // namespace hapi_frontend
