// Settings of the surface-motion estimator (docs/DESIGN.md "Surface
// motion"). Declared once in surface_motion_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {
namespace surface_motion {

struct SurfaceMotionSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/surface_motion/surface_motion_settings.def"
#undef HAPI_FIELD

  // Every table range, then the rules between fields; "" when valid.
  std::string validate() const;
};

HAPI_SETTINGS_VISITOR(SurfaceMotionSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/surface_motion/surface_motion_settings.def"
#undef HAPI_FIELD
}

}  // namespace surface_motion
}  // namespace hapi_eskf
