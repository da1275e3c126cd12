// Checks and text forms of EskfSettings, all driven by the field table
// (the parts' .def lists): the only hand-written rules are those between
// fields (PoolSettings::crossFieldError).
#include "hapi_eskf/settings.hpp"

#include <type_traits>

namespace hapi_eskf {

std::string EskfSettings::validate() const {
  std::string err;
  forEachField(*this, [&](const FieldInfo& f, const auto& v) {
    if (err.empty()) err = rangeError(f, v);
  });
  if (!err.empty()) return err;
  return crossFieldError();
}

std::string setFieldFromText(EskfSettings* s, const std::string& name, const std::string& value) {
  std::string err = "unknown setting '" + name + "'";
  forEachField(*s, [&](const FieldInfo& f, auto& v) {
    if (name != f.name) return;
    using T = std::decay_t<decltype(v)>;
    err = parseValue(value, &v) ? "" : name + " must be " + expectedText<T>() + ", got '" + value + "'";
  });
  return err;
}

const char* toString(BackendAlgorithm a) { return enumToString(a); }

}  // namespace hapi_eskf
