// Declarative settings tables. Every setting is declared ONCE, as one line
//   HAPI_FIELD(type, name, default, range, unit, doc)
// of a .def list (the settings parts' .def lists, settings.hpp; ros/nodelet_params.def for the nodelet's
// own parameters). The struct members with their defaults and forEachField()
// are generated from that list, and everything that needs the names, defaults
// or ranges loops over it: validate(), the ROS parameter reader, the tools'
// key=value overrides and the check of config/eskf.yaml. A setting cannot
// then have two defaults or be forgotten by one reader.
//
// This header holds the pieces every table shares: the allowed range of a
// numeric field, the field's description, the names of enum values, and the
// check and text conversions written once for all of them.
#pragma once

#include <hapi_nodelet_kit/number_range.hpp>

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

namespace hapi_eskf {

// Allowed values of a numeric field (the one range type of every HAPI
// parameter table, hapi_nodelet_kit/number_range.hpp).
using Range = hapi_nodelet_kit::NumberRange;

// What the table says about one field besides its type and default.
struct FieldInfo {
  const char* name;
  Range range;       // numeric fields only
  const char* unit;  // "" when dimensionless
  const char* doc;   // one line
};

// Names of the values of an enum setting, in the order they are listed to a
// user. Specialised next to each enum: static constexpr EnumName<E> kNames[].
template <typename E>
struct EnumName {
  E value;
  const char* name;
};
template <typename E>
struct EnumNames;

template <typename E>
const char* enumToString(E v) {
  for (const auto& n : EnumNames<E>::kNames)
    if (n.value == v) return n.name;
  return "?";
}

template <typename E>
bool enumFromString(const std::string& s, E* out) {
  for (const auto& n : EnumNames<E>::kNames)
    if (s == n.name) {
      *out = n.value;
      return true;
    }
  return false;
}

// "'cpu' or 'cuda'", "'auto', 'trsm' or 'inverse'".
template <typename E>
std::string enumChoices() {
  std::string out;
  const std::size_t n = std::extent<decltype(EnumNames<E>::kNames)>::value;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) out += i + 1 == n ? " or " : ", ";
    out += std::string("'") + EnumNames<E>::kNames[i].name + "'";
  }
  return out;
}

// The value as a user writes it (YAML, command line).
inline std::string valueText(int v) { return std::to_string(v); }
inline std::string valueText(bool v) { return v ? "true" : "false"; }
inline std::string valueText(const std::string& v) { return v; }
inline std::string valueText(double v) {
  std::ostringstream o;
  o << std::setprecision(15) << v;
  return o.str();
}
template <typename E, typename = std::enable_if_t<std::is_enum<E>::value>>
std::string valueText(E v) {
  return enumToString(v);
}

// Parses a value written as text into `*out` (unchanged on failure): whole
// strings only ("12x" is not an int), true/false for bools, an enum's names.
inline bool parseValue(const std::string& s, int* out) {
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    return false;
  *out = static_cast<int>(v);
  return true;
}
inline bool parseValue(const std::string& s, double* out) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') return false;
  *out = v;
  return true;
}
inline bool parseValue(const std::string& s, bool* out) {
  if (s == "true") *out = true;
  else if (s == "false") *out = false;
  else return false;
  return true;
}
inline bool parseValue(const std::string& s, std::string* out) {
  *out = s;
  return true;
}
template <typename E, typename = std::enable_if_t<std::is_enum<E>::value>>
bool parseValue(const std::string& s, E* out) {
  return enumFromString(s, out);
}

// What parseValue accepts for a field of this type, for error messages.
template <typename T>
std::string expectedText() {
  if constexpr (std::is_enum<T>::value) return enumChoices<T>();
  else if constexpr (std::is_same<T, bool>::value) return "true or false";
  else if constexpr (std::is_same<T, int>::value) return "an integer";
  else if constexpr (std::is_same<T, double>::value) return "a number";
  else return "text";
}

// Empty when `v` lies in the field's range, else
// "<prefix><name> must be <range> <unit>, got <v>". Only numbers have ranges.
template <typename T>
std::string rangeError(const FieldInfo& f, const T& v, const char* prefix = "") {
  if constexpr (std::is_arithmetic<T>::value && !std::is_same<T, bool>::value) {
    return hapi_nodelet_kit::outOfRange(std::string(prefix) + f.name, f.range, f.unit, static_cast<double>(v));
  } else {
    (void)f;
    (void)v;
    (void)prefix;
    return "";
  }
}

// The table's description of a field for a --help listing:
// "name (default 2000, in [1, 200000]): doc".
template <typename T>
std::string describeField(const FieldInfo& f, const T& default_value) {
  std::string d = std::string(f.name) + " (default " + valueText(default_value);
  if constexpr (std::is_enum<T>::value) {
    d += ", " + enumChoices<T>();
  } else if constexpr (std::is_arithmetic<T>::value && !std::is_same<T, bool>::value) {
    if (f.range.bounded()) d += ", " + f.range.text();
  }
  if (*f.unit) d += std::string(", ") + f.unit;
  return d + "): " + f.doc;
}

// Declares forEachField(s, visit) for the settings struct T: visit(FieldInfo,
// field) for every field of its table in order, the field `const F&` or `F&`
// as s is const or not. Each table's header follows it with the body that
// includes its .def list.
#define HAPI_SETTINGS_VISITOR(T)                                                                    \
  template <typename Settings, typename Visitor,                                                    \
            std::enable_if_t<std::is_same<std::remove_const_t<Settings>, T>::value, int> = 0> \
  void forEachField(Settings& s, Visitor&& visit)

// `s` seen as its part (a base) Part, const as `s` is: for a composed
// settings struct's forEachField over its parts.
template <typename Part, typename S>
std::conditional_t<std::is_const<S>::value, const Part, Part>& asPart(S& s) {
  return s;
}

}  // namespace hapi_eskf
