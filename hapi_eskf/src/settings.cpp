// Checks and text forms of EskfSettings, all driven by the field table
// (eskf_settings.def): the only hand-written rules are those between fields.
#include "hapi_eskf/settings.hpp"

#include <type_traits>

namespace hapi_eskf {

std::string EskfSettings::validate() const {
  std::string err;
  forEachField(*this, [&](const FieldInfo& f, const auto& v) {
    if (err.empty()) err = rangeError(f, v);
  });
  if (!err.empty()) return err;
  // Ranges that depend on another field.
  if (max_new_landmarks > max_landmarks)
    return "max_new_landmarks must be in [0, max_landmarks], got " + std::to_string(max_new_landmarks);
  if (bootstrap_landmarks > max_landmarks)
    return "bootstrap_landmarks must be in [0, max_landmarks], got " + std::to_string(bootstrap_landmarks);
  return "";
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
const char* toString(BackendKind b) { return enumToString(b); }
const char* toString(Precision p) { return enumToString(p); }
const char* toString(MotionModelKind m) { return enumToString(m); }
bool parseBackendKind(const std::string& s, BackendKind* out) { return enumFromString(s, out); }
bool parsePrecision(const std::string& s, Precision* out) { return enumFromString(s, out); }

}  // namespace hapi_eskf
