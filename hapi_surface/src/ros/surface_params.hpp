// Private (~) parameters of hapi_surface/SurfaceNodelet: the core's table
// (SurfaceSettings) and the nodelet's own (surface_nodelet_params.def), read
// and validated once at start-up.
#pragma once

#include "hapi_surface/surface_settings.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>

#include <string>

namespace hapi_surface {
namespace ros_glue {

struct SurfaceParams {
  SurfaceSettings core;
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "surface_nodelet_params.def"
#undef HAPI_FIELD
  double time_jump_reset = 1.0;  // the stamp guard's (hapi_nodelet_kit), as in every nodelet
};

// Reads every ~ parameter through `reader` into *out (defaults for absent
// ones); a wrong type, a value out of range or a broken rule between fields
// is an error of `reader`, an unknown name a warning.
void readSurfaceParams(hapi_nodelet_kit::ParamReader& reader, SurfaceParams* out);

}  // namespace ros_glue
}  // namespace hapi_surface
