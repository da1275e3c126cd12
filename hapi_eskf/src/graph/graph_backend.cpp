// Graph SLAM's maker (graph_backend.hpp).
#include "hapi_eskf/graph/graph_backend.hpp"

#include "hapi_eskf/backend/associating_backend.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"
#include "hapi_eskf/graph/graph_slam.hpp"

namespace hapi_eskf {
namespace graph {

std::unique_ptr<SlamBackend> makeGraphBackend(const EskfSettings& s, int descriptor_length,
                                              const CameraExtrinsic& /*extrinsic: no IMU model*/,
                                              std::string* error) {
  return makeAssociatingBackend(
      s, descriptor_length,
      [&s](std::string* err) -> std::unique_ptr<AssociatedCore> {
        const GraphSettings settings = graphSettings(s);
        const std::string bad = settings.validate();
        if (!bad.empty()) {
          if (err) *err = bad;
          return nullptr;
        }
        return std::make_unique<GraphSlam>(settings);
      },
      error);
}

}  // namespace graph
}  // namespace hapi_eskf
