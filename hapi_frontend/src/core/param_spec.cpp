// Range texts and value checks of ParamSpec (param_spec.hpp).
#include "hapi_frontend/param_spec.hpp"

#include <cmath>
#include <sstream>

namespace hapi_frontend {

bool NumberRange::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (min_open ? !(v > min) : !(v >= min)) return false;
  if (max_open ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string NumberRange::text() const {
  std::ostringstream os;
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max)
    os << "in " << (min_open ? "(" : "[") << min << ", " << max << (max_open ? ")" : "]");
  else if (has_min)
    os << (min_open ? "> " : ">= ") << min;
  else if (has_max)
    os << (max_open ? "< " : "<= ") << max;
  else
    os << "finite";
  return os.str();
}

namespace {
std::string outOfRange(const ParamSpec& spec, const std::string& got) {
  std::string s = std::string(spec.name) + " must be " + spec.range.text();
  if (spec.unit[0] != '\0') s += std::string(" ") + spec.unit;
  return s + ", got " + got;
}
}  // namespace

std::string checkValue(const ParamSpec& spec, double value) {
  if (spec.range.contains(value)) return "";
  std::ostringstream os;
  os << value;
  return outOfRange(spec, os.str());
}

std::string checkValue(const ParamSpec& spec, int value) {
  if (spec.range.contains(static_cast<double>(value))) return "";
  return outOfRange(spec, std::to_string(value));
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
