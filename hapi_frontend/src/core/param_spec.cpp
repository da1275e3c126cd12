// Value checks of ParamSpec (param_spec.hpp).
#include "hapi_frontend/param_spec.hpp"


namespace hapi_frontend {

std::string checkValue(const ParamSpec& spec, double value) {
  return hapi_nodelet_kit::outOfRange(spec.name, spec.range, spec.unit, value);
}

std::string checkValue(const ParamSpec& spec, int value) {
  return hapi_nodelet_kit::outOfRange(spec.name, spec.range, spec.unit, value);
}

std::string checkValue(const ParamSpec& spec, const std::string& value) {
  if (spec.choices.empty()) {
    if (!value.empty()) return "";
    return std::string(spec.name) + " must not be empty";
  }
  std::string list;
  for (const std::string& c : spec.choices) {
    if (c == value) return "";
    list += (list.empty() ? "" : ", ") + c;
  }
  return std::string(spec.name) + " must be one of " + list + ", got '" + value + "'";
}

}  // namespace hapi_frontend
