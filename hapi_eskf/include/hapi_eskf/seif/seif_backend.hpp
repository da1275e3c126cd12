// The SEIF's maker (backend/slam_backend_maker.hpp): backend_algorithm seif,
// the ES-EKF's host logic over the information-form storage
// (seif_storage.hpp).
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {
namespace seif {

std::unique_ptr<SlamBackend> makeSeifBackend(const EskfSettings& settings, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace seif
}  // namespace hapi_eskf
