// FastSLAM 2.0's maker (fastslam_backend.hpp).
#include "hapi_eskf/fastslam/fastslam_backend.hpp"

#include "hapi_eskf/backend/associating_backend.hpp"
#include "hapi_eskf/fastslam/fastslam2.hpp"
#include "hapi_eskf/fastslam/fastslam_settings.hpp"

namespace hapi_eskf {
namespace fastslam {

std::unique_ptr<SlamBackend> makeFastSlamBackend(const EskfSettings& s, int descriptor_length,
                                                 const CameraExtrinsic& /*extrinsic: no IMU model*/,
                                                 std::string* error) {
  return makeAssociatingBackend(
      s, descriptor_length,
      [&s](std::string* err) -> std::unique_ptr<AssociatedCore> {
        const FastSlamSettings settings = fastSlamSettings(s);
        const std::string bad = settings.validate();
        if (!bad.empty()) {
          if (err) *err = bad;
          return nullptr;
        }
        return std::make_unique<FastSlam2>(settings);
      },
      error);
}

}  // namespace fastslam
}  // namespace hapi_eskf
