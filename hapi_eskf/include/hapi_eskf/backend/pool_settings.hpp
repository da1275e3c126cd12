// The landmark pool and the per-iteration sizes, one part of the settings
// (settings.hpp composes them): the bookkeeping (landmark_book.hpp) reads
// it. Declared once in pool_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

struct PoolSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/backend/pool_settings.def"
#undef HAPI_FIELD

  // Empty when the rules between the fields hold (max_new_landmarks and
  // bootstrap_landmarks <= max_landmarks); the ranges: fieldRangeError.
  std::string crossFieldError() const;
};

HAPI_SETTINGS_VISITOR(PoolSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/backend/pool_settings.def"
#undef HAPI_FIELD
}

}  // namespace hapi_eskf
