// The back-end factory (slam_backend.hpp): backend_algorithm -> implementation.
// Each algorithm lives in its own folder; this file only wires them.
#include "hapi_eskf/slam_backend.hpp"

#include "hapi_eskf/associating_backend.hpp"
#include "hapi_eskf/covariance_backend.hpp"
#include "hapi_eskf/eskf.hpp"
#include "hapi_eskf/fastslam/fastslam2.hpp"
#ifdef HAPI_ESKF_WITH_GRAPH
#include "hapi_eskf/graph/graph_slam.hpp"
#endif
#include "hapi_eskf/seif/seif_storage.hpp"

namespace hapi_eskf {

Mat12 SlamBackend::cameraCovariance() const {
  Mat12 C = Mat12::Zero();
  C.topLeftCorner<6, 6>() = cameraPoseCovariance();
  C.bottomRightCorner<6, 6>().diagonal().setConstant(kUnknownTwistVariance);
  return C;
}

bool slamBackendBuilt(BackendAlgorithm algorithm, std::string* why) {
  switch (algorithm) {
    case BackendAlgorithm::kEskf:
    case BackendAlgorithm::kSeif:
    case BackendAlgorithm::kFastSlam2:
      return true;
    case BackendAlgorithm::kGraph:
#ifdef HAPI_ESKF_WITH_GRAPH
      return true;
#else
      break;  // built without Ceres
#endif
  }
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
  // graph, fastslam2: a core on associated frames behind the shared
  // association and bookkeeping (associating_backend.hpp).
  if (s.backend_algorithm == BackendAlgorithm::kFastSlam2 || s.backend_algorithm == BackendAlgorithm::kGraph) {
    if (s.motion_model != MotionModelKind::kConstantVelocity) {
      if (error) *error = std::string(toString(s.backend_algorithm)) + " supports motion_model constant_velocity only";
      return nullptr;
    }
    std::unique_ptr<AssociatedCore> core;
    if (s.backend_algorithm == BackendAlgorithm::kFastSlam2) {
      const fastslam::FastSlamSettings f = fastslam::fastSlamSettings(s);
      if (error && !f.validate().empty()) *error = f.validate();
      if (!f.validate().empty()) return nullptr;
      core = std::make_unique<fastslam::FastSlam2>(f);
    }
#ifdef HAPI_ESKF_WITH_GRAPH
    if (s.backend_algorithm == BackendAlgorithm::kGraph) {
      const graph::GraphSettings g = graph::graphSettings(s);
      if (error && !g.validate().empty()) *error = g.validate();
      if (!g.validate().empty()) return nullptr;
      core = std::make_unique<graph::GraphSlam>(g);
    }
#endif
    auto backend = std::make_unique<AssociatingBackend>(s, descriptor_length, std::move(core));
    backend->reset(PoseState(), 0.0);
    return backend;
  }
  // seif: the ES-EKF's host logic over the information-form storage.
  std::unique_ptr<CovarianceBackend> storage = s.backend_algorithm == BackendAlgorithm::kSeif
                                                   ? seif::makeSeifStorage(s, descriptor_length, error)
                                                   : makeBackend(s, descriptor_length, error);
  if (!storage) return nullptr;
  return std::make_unique<Eskf>(s, std::move(storage), extrinsic);
}

}  // namespace hapi_eskf
