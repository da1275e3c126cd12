#include "surface_params.hpp"

#include <hapi_nodelet_kit/time_jump_reset_param.hpp>

namespace hapi_surface {
namespace ros_glue {

void readSurfaceParams(hapi_nodelet_kit::ParamReader& reader, SurfaceParams* out) {
  SurfaceParams p;
  auto read = [&](const FieldInfo& f, auto& v) {
    reader.read(f.name, &v);
    const std::string e = rangeError(f, v, "~");
    if (!e.empty()) reader.error(e);
  };
  forEachField(p.core, read);
#define HAPI_FIELD(type, name, default_value, range, unit, doc) read(FieldInfo{#name, range, unit, doc}, p.name);
#include "surface_nodelet_params.def"
#undef HAPI_FIELD
  const std::string rule = reader.ok() ? p.core.validate() : "";
  if (!rule.empty()) reader.error("~" + rule);
  if (p.world_frame.empty()) reader.error("~world_frame must not be empty");
  p.time_jump_reset = hapi_nodelet_kit::readTimeJumpReset(reader);
  if (!p.auto_colour_range && !(p.colour_max > p.colour_min)) reader.error("~colour_max must be > ~colour_min");
  reader.warnAboutUnknown("docs/RUNNING.md \"Surface\", surface_settings.def and surface_nodelet_params.def");
  *out = p;
}

}  // namespace ros_glue
}  // namespace hapi_surface
