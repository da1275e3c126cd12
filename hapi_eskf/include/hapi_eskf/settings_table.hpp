// The range check and the key=value setter of any settings table that has a
// forEachField() (field_table.hpp), written once for the back ends' tables
// (settings.hpp, graph_settings.hpp, fastslam_settings.hpp).
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

// Empty when every field is within its range, else the first offender.
template <typename Settings>
std::string fieldRangeError(const Settings& s) {
  std::string err;
  forEachField(s, [&](const FieldInfo& f, const auto& v) {
    if (err.empty()) err = rangeError(f, v);
  });
  return err;
}

// Sets the field called `name` from its text form; empty on success, else
// why not (unknown name, unparsable value). Ranges: fieldRangeError().
template <typename Settings>
std::string setTableFieldFromText(Settings* s, const std::string& name, const std::string& value) {
  std::string err = "unknown setting '" + name + "'";
  forEachField(*s, [&](const FieldInfo& f, auto& v) {
    if (name != f.name) return;
    using T = std::decay_t<decltype(v)>;
    err = parseValue(value, &v) ? "" : name + " must be " + expectedText<T>() + ", got '" + value + "'";
  });
  return err;
}

}  // namespace hapi_eskf
