// Private (~) parameters of hapi_eskf/SurfaceMotionNodelet: the estimator's
// table (SurfaceMotionSettings) and the nodelet's own
// (surface_motion_nodelet_params.def), read and validated once at start-up;
// ~time_jump_reset is the stamp guard's (hapi_nodelet_kit), as in every
// nodelet.
#pragma once

#include "hapi_eskf/surface_motion/surface_motion_settings.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>

#include <string>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

struct SurfaceMotionParams {
  surface_motion::SurfaceMotionSettings estimator;
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "surface_motion_nodelet_params.def"
#undef HAPI_FIELD
  double time_jump_reset = 1.0;
};

// Reads every ~ parameter through `reader` into *out (defaults for absent
// ones); a wrong type or a value out of its range is an error of `reader`,
// an unknown name a warning.
void readSurfaceMotionParams(hapi_nodelet_kit::ParamReader& reader, SurfaceMotionParams* out);

}  // namespace ros_glue
}  // namespace hapi_eskf
