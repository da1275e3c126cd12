// Checks and text forms of FastSlamSettings, driven by fastslam_settings.def.
#include "hapi_eskf/fastslam/fastslam_settings.hpp"

#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/settings_table.hpp"

namespace hapi_eskf {
namespace fastslam {

std::string FastSlamSettings::validate() const {
  const std::string err = fieldRangeError(*this);
  if (!err.empty()) return err;
  if (!(sigma_acceleration >= 0.0) || !(sigma_angular_acceleration >= 0.0))
    return "sigma_acceleration and sigma_angular_acceleration must be >= 0";
  return "";
}

std::string setFieldFromText(FastSlamSettings* s, const std::string& name, const std::string& value) {
  return setTableFieldFromText(s, name, value);
}

FastSlamSettings fastSlamSettings(const EskfSettings& s) {
  FastSlamSettings f;
  static_cast<FastSlamTable&>(f) = s.fastslam;
  f.sigma_acceleration = s.sigma_acceleration;
  f.sigma_angular_acceleration = s.sigma_angular_acceleration;
  return f;
}

}  // namespace fastslam
}  // namespace hapi_eskf
