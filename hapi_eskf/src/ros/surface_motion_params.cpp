#include "surface_motion_params.hpp"

#include <hapi_nodelet_kit/time_jump_reset_param.hpp>

namespace hapi_eskf {
namespace ros_glue {
namespace {

template <typename Visitor>
void forEachNodeletField(SurfaceMotionParams& p, Visitor&& visit) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, p.name);
#include "surface_motion_nodelet_params.def"
#undef HAPI_FIELD
}

}  // namespace

void readSurfaceMotionParams(hapi_nodelet_kit::ParamReader& reader, SurfaceMotionParams* out) {
  SurfaceMotionParams p;
  auto read = [&](const FieldInfo& f, auto& v) {
    reader.read(f.name, &v);
    const std::string e = rangeError(f, v, "~");
    if (!e.empty()) reader.error(e);
  };
  surface_motion::forEachField(p.estimator, read);
  forEachNodeletField(p, read);
  // The rules between fields (the ranges are reported above, one per field).
  const std::string rule = reader.ok() ? p.estimator.validate() : "";
  if (!rule.empty()) reader.error("~" + rule);
  p.time_jump_reset = hapi_nodelet_kit::readTimeJumpReset(reader);
  reader.warnAboutUnknown("docs/RUNNING.md \"Surface motion\" and surface_motion_settings.def");
  *out = p;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
