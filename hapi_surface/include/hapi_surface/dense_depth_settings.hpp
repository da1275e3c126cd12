// Settings of the dense depth matcher (docs/DESIGN.md "Dense depth"),
// declared once in dense_depth_settings.def.
#pragma once

#include <hapi_eskf/field_table.hpp>

#include <string>
#include <type_traits>

namespace hapi_surface {

using hapi_eskf::FieldInfo;
using hapi_eskf::Range;

struct DenseDepthSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_surface/dense_depth_settings.def"
#undef HAPI_FIELD

  // Every table range, then the rules between fields; "" when valid.
  std::string validate() const;
};

HAPI_SETTINGS_VISITOR(DenseDepthSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_surface/dense_depth_settings.def"
#undef HAPI_FIELD
}

}  // namespace hapi_surface
