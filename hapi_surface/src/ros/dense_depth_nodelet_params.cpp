// Reading DenseDepthNodelet's ~ parameters (dense_depth_nodelet_params.hpp).
#include "dense_depth_nodelet_params.hpp"

#include <hapi_eskf/settings_table.hpp>

namespace hapi_surface {

void readDenseDepthParams(hapi_nodelet_kit::ParamReader& reader, DenseDepthNodeletParams* out) {
  DenseDepthNodeletParams p;
  forEachNodeletField(p, [&](const FieldInfo& f, auto& v) {
    reader.read(f.name, &v);
    const std::string e = hapi_eskf::rangeError(f, v, "~");
    if (!e.empty()) reader.error(e);
  });
  // The rules between fields (the ranges are reported above, one per field).
  const std::string rule = reader.ok() ? p.depth.validate() : "";
  if (!rule.empty()) reader.error("~" + rule);
  if (p.image_transport.empty()) reader.error("~image_transport must not be empty");
  reader.warnAboutUnknown("docs/RUNNING.md \"Dense depth\" and dense_depth_settings.def");
  *out = p;
}

std::string setDenseDepthParam(DenseDepthNodeletParams* p, const std::string& name, const std::string& value) {
  std::string err = "unknown parameter '" + name + "'";
  forEachNodeletField(*p, [&](const FieldInfo& f, auto& v) {
    if (name != f.name) return;
    using T = std::decay_t<decltype(v)>;
    T parsed = v;
    if (!hapi_eskf::parseValue(value, &parsed)) {
      err = name + " must be " + hapi_eskf::expectedText<T>() + ", got '" + value + "'";
      return;
    }
    err = hapi_eskf::rangeError(f, parsed);
    if (err.empty()) v = parsed;
  });
  return err;
}

}  // namespace hapi_surface
