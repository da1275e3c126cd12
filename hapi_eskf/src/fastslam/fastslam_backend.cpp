// FastSLAM 2.0's maker (fastslam2.hpp makeFastSlamBackend).
#include "hapi_eskf/fastslam/fastslam2.hpp"

#include "hapi_eskf/backend/associating_backend.hpp"
#include "hapi_eskf/fastslam/fastslam_settings.hpp"

namespace hapi_eskf {
namespace fastslam {

std::unique_ptr<SlamBackend> makeFastSlamBackend(const EskfSettings& s, int descriptor_length,
                                                 const CameraExtrinsic& /*extrinsic: no IMU model*/,
                                                 std::string* error) {
  return makeAssociatingBackendOf<FastSlam2>(s, descriptor_length, fastSlamSettings(s), error);
}

}  // namespace fastslam
}  // namespace hapi_eskf
