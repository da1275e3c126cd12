// Checks and text forms of EskfSettings, all driven by the parts' tables
// (settings_table.hpp, as every table's): the only hand-written rules are those between
// fields (PoolSettings::crossFieldError).
#include "hapi_eskf/settings.hpp"

#include "hapi_eskf/settings_table.hpp"

namespace hapi_eskf {

std::string EskfSettings::validate() const {
  const std::string err = fieldRangeError(*this);
  if (!err.empty()) return err;
  return crossFieldError();
}

std::string setFieldFromText(EskfSettings* s, const std::string& name, const std::string& value) {
  return setTableFieldFromText(s, name, value);
}

const char* toString(BackendAlgorithm a) { return enumToString(a); }

}  // namespace hapi_eskf
