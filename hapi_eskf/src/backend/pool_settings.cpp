// The rules between the pool's fields (pool_settings.hpp).
#include "hapi_eskf/backend/pool_settings.hpp"

namespace hapi_eskf {

std::string PoolSettings::crossFieldError() const {
  if (max_new_landmarks > max_landmarks)
    return "max_new_landmarks must be in [0, max_landmarks], got " + std::to_string(max_new_landmarks);
  if (bootstrap_landmarks > max_landmarks)
    return "bootstrap_landmarks must be in [0, max_landmarks], got " + std::to_string(bootstrap_landmarks);
  return "";
}

}  // namespace hapi_eskf
