// The declaration of one front-end setting, written once: its name (the ROS
// private parameter's name), allowed values, unit and meaning. Its type and
// default are those of the field it is declared for. A settings struct lists
// its fields with their declarations in a visit(ParamVisitor&) function; the
// core's validate() and the nodelet's parameter reader both walk that list, so
// no range is ever written twice. ROS-free.
#pragma once

#include <hapi_nodelet_kit/number_range.hpp>

#include <string>
#include <utility>
#include <vector>

namespace hapi_frontend {

// Allowed values of a number (the one range type of every HAPI parameter
// table, hapi_nodelet_kit/number_range.hpp).
using NumberRange = hapi_nodelet_kit::NumberRange;

struct ParamSpec {
  const char* name = "";
  const char* unit = "";  // "" when dimensionless
  const char* doc = "";
  NumberRange range;                 // int and double fields
  std::vector<std::string> choices;  // string fields; empty: any non-empty string
  // An older name of the same parameter, still accepted with a warning.
  const char* deprecated_name = nullptr;
  // true: a core tuning value that is not a ROS parameter (validated, never
  // read from the parameter server).
  bool internal = false;

  static ParamSpec number(const char* name, NumberRange range, const char* unit, const char* doc) {
    ParamSpec s;
    s.name = name;
    s.range = range;
    s.unit = unit;
    s.doc = doc;
    return s;
  }
  static ParamSpec flag(const char* name, const char* doc) { return number(name, NumberRange(), "", doc); }
  // choices empty: any non-empty string.
  static ParamSpec text(const char* name, std::vector<std::string> choices, const char* doc) {
    ParamSpec s = number(name, NumberRange(), "", doc);
    s.choices = std::move(choices);
    return s;
  }
  ParamSpec renamedFrom(const char* old_name) const {
    ParamSpec s = *this;
    s.deprecated_name = old_name;
    return s;
  }
  ParamSpec coreOnly() const {
    ParamSpec s = *this;
    s.internal = true;
    return s;
  }
};

// Empty when `value` is allowed by `spec`, else "<name> must be <allowed>
// [unit], got <value>".
std::string checkValue(const ParamSpec& spec, double value);
std::string checkValue(const ParamSpec& spec, int value);
std::string checkValue(const ParamSpec& spec, const std::string& value);
inline std::string checkValue(const ParamSpec&, bool) { return ""; }

// Receives each field of a settings struct with its declaration.
class ParamVisitor {
 public:
  virtual ~ParamVisitor() = default;
  virtual void visit(const ParamSpec& spec, bool& value) = 0;
  virtual void visit(const ParamSpec& spec, int& value) = 0;
  virtual void visit(const ParamSpec& spec, double& value) = 0;
  virtual void visit(const ParamSpec& spec, std::string& value) = 0;
};

// Collects the checkValue() message of every field that violates its
// declaration.
class RangeChecker : public ParamVisitor {
 public:
  void visit(const ParamSpec& spec, bool& value) override { add(checkValue(spec, value)); }
  void visit(const ParamSpec& spec, int& value) override { add(checkValue(spec, value)); }
  void visit(const ParamSpec& spec, double& value) override { add(checkValue(spec, value)); }
  void visit(const ParamSpec& spec, std::string& value) override { add(checkValue(spec, value)); }
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  void add(std::string problem) {
    if (!problem.empty()) problems_.push_back(std::move(problem));
  }
  std::vector<std::string> problems_;
};

// The checkValue() message of every field of `settings` (any struct with
// visit(ParamVisitor&)) that violates its declaration.
template <typename Settings>
std::vector<std::string> rangeProblems(Settings settings) {  // a copy: visit() hands out mutable fields
  RangeChecker check;
  settings.visit(check);
  return check.problems();
}

// Adds "<a> must be <op> <b>, got <va> and <vb>" to *problems unless ok: a
// relation between two settings.
void checkRelation(bool ok, const std::string& a, double va, const char* op, const std::string& b, double vb,
                   std::vector<std::string>* problems);

// problems joined with "; ", empty when there are none.
std::string joinProblems(const std::vector<std::string>& problems);

// Sets the one field declared as `name` from its text, the way the offline
// tools take settings on their command lines (name=value): "true"/"false" or
// 1/0 for flags, whole numbers for int fields; the declared range applies.
class TextSetter : public ParamVisitor {
 public:
  TextSetter(std::string name, std::string value) : name_(std::move(name)), value_(std::move(value)) {}
  void visit(const ParamSpec& spec, bool& value) override;
  void visit(const ParamSpec& spec, int& value) override;
  void visit(const ParamSpec& spec, double& value) override;
  void visit(const ParamSpec& spec, std::string& value) override;
  // Empty when the field was set; else why not (unknown name, not a number,
  // outside the declared range); the field is then unchanged.
  std::string error() const { return found_ ? error_ : "unknown parameter '" + name_ + "'"; }

 private:
  bool matches(const ParamSpec& spec);
  std::string name_, value_, error_;
  bool found_ = false;
};

// setFromText(&params, "fast_threshold", "8"): TextSetter over any settings
// struct with visit(ParamVisitor&); returns its error().
template <typename Settings>
std::string setFromText(Settings* settings, const std::string& name, const std::string& value) {
  TextSetter setter(name, value);
  settings->visit(setter);
  return setter.error();
}

}  // namespace hapi_frontend
