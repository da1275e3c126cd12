// The SEIF's settings (docs/DESIGN.md "SEIF"), one part of the settings
// (settings.hpp composes them; there and as ROS parameters they are
// seif_<name>). Declared once in seif_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {
namespace seif {

struct SeifSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/seif/seif_settings.def"
#undef HAPI_FIELD
};

HAPI_SETTINGS_VISITOR(SeifSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/seif/seif_settings.def"
#undef HAPI_FIELD
}

}  // namespace seif
}  // namespace hapi_eskf
