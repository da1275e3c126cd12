// Settings of the surface core, declared once in surface_settings.def.
#pragma once

#include <hapi_nodelet_kit/number_range.hpp>

#include <string>
#include <type_traits>

namespace hapi_surface {

using Range = hapi_nodelet_kit::NumberRange;

// What the table says about one field besides its type and default.
struct FieldInfo {
  const char* name;
  Range range;
  const char* unit;
  const char* doc;
};

struct SurfaceSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_surface/surface_settings.def"
#undef HAPI_FIELD

  // Every table range, then the rules between fields; "" when valid.
  std::string validate() const;
};

// visit(FieldInfo, field) for every field of the table, in order.
template <typename S, typename Visitor,
          std::enable_if_t<std::is_same<std::remove_const_t<S>, SurfaceSettings>::value, int> = 0>
void forEachField(S& s, Visitor&& visit) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_surface/surface_settings.def"
#undef HAPI_FIELD
}

// "" when `v` lies in the field's range, else "<prefix><name> must be ...".
// Strings and bools have no range.
template <typename T>
std::string rangeError(const FieldInfo& f, const T& v, const char* prefix = "") {
  if constexpr (std::is_arithmetic<T>::value && !std::is_same<T, bool>::value)
    return hapi_nodelet_kit::outOfRange(std::string(prefix) + f.name, f.range, f.unit, static_cast<double>(v));
  else
    return "";
}

}  // namespace hapi_surface
