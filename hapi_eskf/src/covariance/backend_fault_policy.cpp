// Decisions after a backend fault (backend_fault_policy.hpp).
#include "hapi_eskf/covariance/backend_fault_policy.hpp"

namespace hapi_eskf {

const char* toString(FaultAction a) {
  switch (a) {
    case FaultAction::kRestart: return "restart on a new backend";
    case FaultAction::kFallBackToCpu: return "fall back to the cpu backend";
    case FaultAction::kStop: return "stop";
  }
  return "unknown";
}

FaultAction BackendFaultPolicy::giveUp(BackendKind kind) const {
  // The CPU backend is the last resort: a fault there is not a device's.
  if (kind == BackendKind::kCuda && allow_cpu_fallback_) return FaultAction::kFallBackToCpu;
  return FaultAction::kStop;
}

FaultAction BackendFaultPolicy::onFault(BackendKind kind) {
  ++consecutive_;
  if (consecutive_ <= max_restarts_) return FaultAction::kRestart;
  return giveUp(kind);
}

FaultAction BackendFaultPolicy::onCreateFailed(BackendKind kind) const { return giveUp(kind); }

}  // namespace hapi_eskf
