// The back-end factory (slam_backend.hpp): backend_algorithm -> implementation.
// Each algorithm lives in its own folder; this file only wires them.
#include "hapi_eskf/slam_backend.hpp"

#include "hapi_eskf/covariance_backend.hpp"
#include "hapi_eskf/eskf.hpp"
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
      return true;
    case BackendAlgorithm::kGraph:
    case BackendAlgorithm::kFastSlam2:
      break;
  }
  if (why)
    *why = std::string("backend_algorithm '") + toString(algorithm) +
           "' is not built into this hapi_eskf (available: eskf, seif)";
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
  // seif: the ES-EKF's host logic over the information-form storage.
  std::unique_ptr<CovarianceBackend> storage = s.backend_algorithm == BackendAlgorithm::kSeif
                                                   ? seif::makeSeifStorage(s, descriptor_length, error)
                                                   : makeBackend(s, descriptor_length, error);
  if (!storage) return nullptr;
  return std::make_unique<Eskf>(s, std::move(storage), extrinsic);
}

}  // namespace hapi_eskf
