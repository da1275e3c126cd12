// Settings of the FastSLAM 2.0 back end (docs/DESIGN.md "FastSLAM 2.0"),
// declared once in fastslam_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {
namespace fastslam {

struct FastSlamSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FIELD

  std::string validate() const;  // empty when valid
};

template <typename Settings, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Settings>, FastSlamSettings>::value>>
void forEachField(Settings& s, Visitor&& visit) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FIELD
}

std::string setFieldFromText(FastSlamSettings* s, const std::string& name, const std::string& value);

}  // namespace fastslam
}  // namespace hapi_eskf
