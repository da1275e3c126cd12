// Text of every Status (diagnostics, tools, test messages).
#include "hapi_eskf/status.hpp"

namespace hapi_eskf {

const char* toString(Status s) {
  switch (s) {
    case Status::kOk: return "ok";
    case Status::kEmptyInput: return "empty input";
    case Status::kNonFinite: return "non-finite value (NaN/Inf)";
    case Status::kDuplicateId: return "duplicate id or slot";
    case Status::kCapacityExceeded: return "capacity exceeded";
    case Status::kNotPositiveDefinite: return "covariance not positive definite";
    case Status::kInvalidArgument: return "invalid argument";
    case Status::kNotInitialised: return "not initialised";
    case Status::kAwaitingImu: return "awaiting IMU samples for the gravity alignment";
    case Status::kBackendUnavailable: return "backend unavailable";
    case Status::kBackendError: return "backend error";
  }
  return "unknown status";
}

}  // namespace hapi_eskf
