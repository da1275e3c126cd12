// How an algorithm plugs into the back-end factory (slam_backend_factory.hpp):
// each algorithm folder (eskf/, seif/, graph/, fastslam/) offers one function
// of this shape that checks its part of the settings and builds its
// SlamBackend. nullptr with *error when it cannot.
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {

// `descriptor_length`: bytes per descriptor of the stream; `extrinsic`: the
// camera in the IMU frame (IMU motion models). The settings are valid
// (EskfSettings::validate) when the factory calls a maker.
using SlamBackendMaker = std::unique_ptr<SlamBackend> (*)(const EskfSettings& settings, int descriptor_length,
                                                         const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace hapi_eskf
