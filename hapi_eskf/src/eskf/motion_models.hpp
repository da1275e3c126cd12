// The concrete motion models (motion_model.hpp), one source file each;
// makeMotionModel (motion_model.cpp) picks one from the settings.
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"

namespace hapi_eskf {

std::unique_ptr<MotionModel> makeCameraMotionModel(const EskfSettings& s, const CameraExtrinsic& e, bool use_gyro);
std::unique_ptr<MotionModel> makeInertialMotionModel(const EskfSettings& s, const CameraExtrinsic& e);

}  // namespace hapi_eskf
