// The ES-EKF's maker (backend/slam_backend_maker.hpp): backend_algorithm eskf,
// the filter over the storage the settings name (storage_factory.hpp).
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {

std::unique_ptr<SlamBackend> makeEskfBackend(const EskfSettings& settings, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace hapi_eskf
