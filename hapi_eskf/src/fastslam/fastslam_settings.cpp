// Checks and text forms of FastSlamSettings, driven by fastslam_settings.def.
#include "hapi_eskf/fastslam/fastslam_settings.hpp"

#include "hapi_eskf/settings_table.hpp"

namespace hapi_eskf {
namespace fastslam {

std::string FastSlamSettings::validate() const { return fieldRangeError(*this); }

std::string setFieldFromText(FastSlamSettings* s, const std::string& name, const std::string& value) {
  return setTableFieldFromText(s, name, value);
}

}  // namespace fastslam
}  // namespace hapi_eskf
