// FastSLAM 2.0's maker (backend/slam_backend_maker.hpp): backend_algorithm
// fastslam2, the particle filter (fastslam2.hpp) behind the shared
// association and bookkeeping (backend/associating_backend.hpp).
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {
namespace fastslam {

std::unique_ptr<SlamBackend> makeFastSlamBackend(const EskfSettings& settings, int descriptor_length,
                                               const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace fastslam
}  // namespace hapi_eskf
