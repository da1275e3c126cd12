// Value checks of ParamSpec and the text setter of the offline tools
// (param_spec.hpp).
#include "hapi_frontend/param_spec.hpp"

#include <cstdlib>
#include <sstream>

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

void checkRelation(bool ok, const std::string& a, double va, const char* op, const std::string& b, double vb,
                   std::vector<std::string>* problems) {
  if (ok) return;
  std::ostringstream os;
  os << a << " must be " << op << " " << b << ", got " << va << " and " << vb;
  problems->push_back(os.str());
}

std::string joinProblems(const std::vector<std::string>& problems) {
  std::string all;
  for (const std::string& p : problems) all += (all.empty() ? "" : "; ") + p;
  return all;
}

bool TextSetter::matches(const ParamSpec& spec) {
  if (name_ != spec.name) return false;
  found_ = true;
  return true;
}

void TextSetter::visit(const ParamSpec& spec, bool& value) {
  if (!matches(spec)) return;
  if (value_ == "true" || value_ == "1") value = true;
  else if (value_ == "false" || value_ == "0") value = false;
  else error_ = name_ + " must be true or false, got '" + value_ + "'";
}

void TextSetter::visit(const ParamSpec& spec, int& value) {
  if (!matches(spec)) return;
  char* end = nullptr;
  const long v = std::strtol(value_.c_str(), &end, 10);
  if (value_.empty() || *end != '\0' || v < -2147483647L || v > 2147483647L) {
    error_ = name_ + " must be a whole number, got '" + value_ + "'";
    return;
  }
  error_ = checkValue(spec, static_cast<int>(v));
  if (error_.empty()) value = static_cast<int>(v);
}

void TextSetter::visit(const ParamSpec& spec, double& value) {
  if (!matches(spec)) return;
  char* end = nullptr;
  const double v = std::strtod(value_.c_str(), &end);
  if (value_.empty() || *end != '\0') {
    error_ = name_ + " must be a number, got '" + value_ + "'";
    return;
  }
  error_ = checkValue(spec, v);
  if (error_.empty()) value = v;
}

void TextSetter::visit(const ParamSpec& spec, std::string& value) {
  if (!matches(spec)) return;
  error_ = checkValue(spec, value_);
  if (error_.empty()) value = value_;
}

}  // namespace hapi_frontend
