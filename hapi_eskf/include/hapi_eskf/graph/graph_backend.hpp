// Graph SLAM's maker (backend/slam_backend_maker.hpp): backend_algorithm graph,
// the sliding-window graph (graph_slam.hpp) behind the shared association
// and bookkeeping (backend/associating_backend.hpp).
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {
namespace graph {

std::unique_ptr<SlamBackend> makeGraphBackend(const EskfSettings& settings, int descriptor_length,
                                               const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace graph
}  // namespace hapi_eskf
