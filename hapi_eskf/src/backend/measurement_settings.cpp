// The frame-shared vision error's covariance (measurement_settings.hpp,
// docs/DESIGN.md "Frame-shared vision error").
#include "hapi_eskf/backend/measurement_settings.hpp"

namespace hapi_eskf {

Mat6 MeasurementSettings::frameErrorCameraCovariance() const {
  const double st = frame_translation_sigma, sr = frame_rotation_sigma, sz = frame_optical_axis_sigma;
  Mat6 C = Mat6::Zero();
  C.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sz * sz;
  return C;
}

}  // namespace hapi_eskf
