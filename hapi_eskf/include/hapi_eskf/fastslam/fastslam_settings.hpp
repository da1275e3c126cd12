// Settings of the FastSLAM 2.0 back end (docs/DESIGN.md "FastSLAM 2.0"),
// declared once in fastslam_settings.def; in the filter's table
// (EskfSettings, the ROS parameters) they are fastslam_<name>, and
// fastSlamSettings() reads them there.
#pragma once

#include "hapi_eskf/field_table.hpp"
#include "hapi_eskf/settings.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {
namespace fastslam {

struct FastSlamSettings {
#define HAPI_FASTSLAM_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FASTSLAM_FIELD
  // The velocity random walks of the motion prior: the filter's own settings
  // (eskf_settings.def). Zero is allowed here (a motion without rotation
  // noise: the linear-Gaussian check of test_fastslam.cpp).
  double sigma_acceleration = EskfSettings().sigma_acceleration;
  double sigma_angular_acceleration = EskfSettings().sigma_angular_acceleration;

  std::string validate() const;  // empty when valid
};

template <typename Settings, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Settings>, FastSlamSettings>::value>>
void forEachField(Settings& s, Visitor&& visit) {
#define HAPI_FASTSLAM_FIELD(type, name, default_value, range, unit, doc) \
  visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FASTSLAM_FIELD
}

std::string setFieldFromText(FastSlamSettings* s, const std::string& name, const std::string& value);

// The fastslam_* fields and the motion prior of the filter's settings.
FastSlamSettings fastSlamSettings(const EskfSettings& s);

}  // namespace fastslam
}  // namespace hapi_eskf
