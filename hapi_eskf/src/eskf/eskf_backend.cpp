// The ES-EKF's maker (eskf.hpp makeEskfBackend).
#include "hapi_eskf/eskf/eskf.hpp"

#include "hapi_eskf/eskf/storage_factory.hpp"

namespace hapi_eskf {

std::unique_ptr<SlamBackend> makeEskfBackend(const EskfSettings& s, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error) {
  std::unique_ptr<CovarianceBackend> storage = makeBackend(s, descriptor_length, error);
  if (!storage) return nullptr;
  return std::make_unique<Eskf>(s, std::move(storage), extrinsic);
}

}  // namespace hapi_eskf
