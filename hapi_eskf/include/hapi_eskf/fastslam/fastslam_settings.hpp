// Settings of the FastSLAM 2.0 back end (docs/DESIGN.md "FastSLAM 2.0"),
// declared once in fastslam_settings.def; in the filter's
// settings (EskfSettings::fastslam; as ROS parameters fastslam_<name>) they
// are the table FastSlamTable, and fastSlamSettings() adds the motion prior.
#pragma once

#include "hapi_eskf/backend/motion_settings.hpp"
#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

struct EskfSettings;

namespace fastslam {

// The table: what the user sets.
struct FastSlamTable {
#define HAPI_FASTSLAM_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FASTSLAM_FIELD
};

HAPI_SETTINGS_VISITOR(FastSlamTable) {
#define HAPI_FASTSLAM_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FASTSLAM_FIELD
}

// What the algorithm runs with: its table and what it takes from the
// shared parts.
struct FastSlamSettings : FastSlamTable {
  // The velocity random walks of the motion prior: the filter's own settings
  // (backend/motion_settings.def). Zero is allowed here (a motion without rotation
  // noise: the linear-Gaussian check of test_fastslam.cpp).
  double sigma_acceleration = MotionSettings().sigma_acceleration;
  double sigma_angular_acceleration = MotionSettings().sigma_angular_acceleration;

  std::string validate() const;  // empty when valid
};

// The table's fields of FastSlamSettings (the shared parts' are not settings of
// this algorithm).
HAPI_SETTINGS_VISITOR(FastSlamSettings) {
  forEachField(asPart<FastSlamTable>(s), visit);
}

std::string setFieldFromText(FastSlamSettings* s, const std::string& name, const std::string& value);

// The algorithm's part of the filter's settings (EskfSettings::fastslam) with the
// motion prior of the shared parts.
FastSlamSettings fastSlamSettings(const EskfSettings& s);

}  // namespace fastslam
}  // namespace hapi_eskf
