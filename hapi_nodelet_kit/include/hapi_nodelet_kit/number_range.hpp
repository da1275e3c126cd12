// NumberRange: the allowed values of a numeric parameter, and the one wording
// of "out of range". ROS-free and header-only, so the ROS-free cores'
// settings tables (hapi_eskf's settings.hpp, hapi_frontend's
// PipelineParams) and the nodelets' own parameters (~time_jump_reset) all
// declare their ranges with this one type and report a violation with the
// same text: "<name> must be <range>[ <unit>], got <value>".
#pragma once

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

namespace hapi_nodelet_kit {

// An interval whose ends are open or closed; an infinite end is no bound.
// Every allowed value is also finite (NaN and inf never are).
struct NumberRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  static constexpr NumberRange any() { return NumberRange{}; }
  static constexpr NumberRange closed(double a, double b) { return NumberRange{a, b, false, false}; }
  static constexpr NumberRange open(double a, double b) { return NumberRange{a, b, true, true}; }
  static constexpr NumberRange openClosed(double a, double b) { return NumberRange{a, b, true, false}; }
  static constexpr NumberRange closedOpen(double a, double b) { return NumberRange{a, b, false, true}; }
  static constexpr NumberRange atLeast(double a) {
    return NumberRange{a, std::numeric_limits<double>::infinity(), false, false};
  }
  static constexpr NumberRange above(double a) {
    return NumberRange{a, std::numeric_limits<double>::infinity(), true, false};
  }

  bool bounded() const { return std::isfinite(lo) || std::isfinite(hi); }
  bool contains(double v) const {
    if (!std::isfinite(v)) return false;
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  // "in [1, 12]", "in (0, 1]", ">= 0", "> 0", "< 5"; "finite" when unbounded.
  std::string text() const {
    std::ostringstream o;
    o << std::setprecision(15);
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    if (has_lo && has_hi)
      o << "in " << (lo_open ? '(' : '[') << lo << ", " << hi << (hi_open ? ')' : ']');
    else if (has_lo)
      o << (lo_open ? "> " : ">= ") << lo;
    else if (has_hi)
      o << (hi_open ? "< " : "<= ") << hi;
    else
      o << "finite";
    return o.str();
  }
};

// "" when `value` lies in `range`, else "<name> must be <range>[ <unit>],
// got <value>" (15 significant digits, so an integer prints as itself).
inline std::string outOfRange(const std::string& name, const NumberRange& range, const std::string& unit,
                              double value) {
  if (range.contains(value)) return "";
  std::ostringstream o;
  o << std::setprecision(15) << name << " must be " << range.text();
  if (!unit.empty()) o << ' ' << unit;
  o << ", got " << value;
  return o.str();
}

}  // namespace hapi_nodelet_kit
