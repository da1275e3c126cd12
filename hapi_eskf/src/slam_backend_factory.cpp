// The back-end factory (slam_backend_factory.hpp): one table from
// backend_algorithm to the algorithm's maker. The only file that includes
// every algorithm folder; the algorithms and the shared services below them
// include none of it.
#include "hapi_eskf/slam_backend_factory.hpp"

#include "hapi_eskf/backend/slam_backend_maker.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/fastslam/fastslam2.hpp"
#ifdef HAPI_ESKF_WITH_GRAPH
#include "hapi_eskf/graph/graph_slam.hpp"
#endif
#include "hapi_eskf/seif/seif_storage.hpp"

namespace hapi_eskf {
namespace {

// nullptr: not built into this library.
SlamBackendMaker makerOf(BackendAlgorithm algorithm) {
  switch (algorithm) {
    case BackendAlgorithm::kEskf:
      return &makeEskfBackend;
    case BackendAlgorithm::kSeif:
      return &seif::makeSeifBackend;
    case BackendAlgorithm::kFastSlam2:
      return &fastslam::makeFastSlamBackend;
    case BackendAlgorithm::kGraph:
#ifdef HAPI_ESKF_WITH_GRAPH
      return &graph::makeGraphBackend;
#else
      return nullptr;  // built without Ceres
#endif
  }
  return nullptr;
}

}  // namespace

bool slamBackendBuilt(BackendAlgorithm algorithm, std::string* why) {
  if (makerOf(algorithm) != nullptr) return true;
  if (why)
    *why = std::string("backend_algorithm '") + toString(algorithm) +
           "' is not built into this hapi_eskf (Graph SLAM needs Ceres, libceres-dev; available: eskf, seif, "
           "fastslam2)";
  return false;
}

std::unique_ptr<SlamBackend> makeSlamBackend(const EskfSettings& s, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error) {
  const std::string bad = s.validate();
  if (!bad.empty()) {
    if (error) *error = bad;
    return nullptr;
  }
  if (!slamBackendBuilt(s.backend_algorithm, error)) return nullptr;
  return makerOf(s.backend_algorithm)(s, descriptor_length, extrinsic, error);
}

}  // namespace hapi_eskf
