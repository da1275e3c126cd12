// The defaults of the back-end interface (slam_backend.hpp).
#include "hapi_eskf/backend/slam_backend.hpp"

namespace hapi_eskf {

Mat12 SlamBackend::cameraCovariance() const {
  Mat12 C = Mat12::Zero();
  C.topLeftCorner<6, 6>() = cameraPoseCovariance();
  C.bottomRightCorner<6, 6>().diagonal().setConstant(kUnknownTwistVariance);
  return C;
}

}  // namespace hapi_eskf
