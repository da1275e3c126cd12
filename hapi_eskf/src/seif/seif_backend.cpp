// The SEIF's maker (seif_storage.hpp makeSeifBackend).
#include "hapi_eskf/seif/seif_storage.hpp"

#include "hapi_eskf/eskf/eskf.hpp"

namespace hapi_eskf {
namespace seif {

std::unique_ptr<SlamBackend> makeSeifBackend(const EskfSettings& s, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error) {
  std::unique_ptr<CovarianceBackend> storage = makeSeifStorage(s, descriptor_length, error);
  if (!storage) return nullptr;
  return std::make_unique<Eskf>(s, std::move(storage), extrinsic);
}

}  // namespace seif
}  // namespace hapi_eskf
