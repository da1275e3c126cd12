// Graph SLAM's maker (graph_slam.hpp makeGraphBackend).
#include "hapi_eskf/graph/graph_slam.hpp"

#include "hapi_eskf/backend/associating_backend.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"

namespace hapi_eskf {
namespace graph {

std::unique_ptr<SlamBackend> makeGraphBackend(const EskfSettings& s, int descriptor_length,
                                              const CameraExtrinsic& /*extrinsic: no IMU model*/,
                                              std::string* error) {
  return makeAssociatingBackendOf<GraphSlam>(s, descriptor_length, graphSettings(s), error);
}

}  // namespace graph
}  // namespace hapi_eskf
