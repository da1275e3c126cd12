// The vision measurement model every back end shares, one part of the
// settings (settings.hpp composes them): the re-detection noise, the
// frame-shared vision error and first-estimate linearisation. Declared once
// in measurement_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"
#include "hapi_eskf/types.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

struct MeasurementSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/backend/measurement_settings.def"
#undef HAPI_FIELD

  // Sigma_f in the camera frame [dp, dtheta] (frame_translation_sigma on each
  // axis, frame_rotation_sigma about x and y, frame_optical_axis_sigma about
  // the optical axis): the ES-EKF's frame error block and the floor Graph
  // SLAM adds to its tracked pose.
  Mat6 frameErrorCameraCovariance() const;
  bool anyFrameError() const {
    return frame_rotation_sigma > 0.0 || frame_optical_axis_sigma > 0.0 || frame_translation_sigma > 0.0;
  }
};

HAPI_SETTINGS_VISITOR(MeasurementSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/backend/measurement_settings.def"
#undef HAPI_FIELD
}

}  // namespace hapi_eskf
