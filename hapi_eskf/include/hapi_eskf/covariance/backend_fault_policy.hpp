// What the owner of a filter does after its covariance backend failed during
// a frame (Status::kBackendError: a CUDA, cuBLAS or cuSOLVER call failed,
// e.g. the device ran out of memory or was lost). The frame is dropped in
// every case; the backend's state (C half-updated) is not trusted any more,
// so the filter is never continued on it (docs/RELIABILITY.md "GPU faults"):
//   kRestart       a new backend of the same kind, the filter started again
//                  from the next frame (transient faults: a freed device
//                  recovers);
//   kFallBackToCpu after max_restarts consecutive faults, or when a new CUDA
//                  backend cannot be created, with allow_cpu_fallback;
//   kStop          otherwise: the filter stops cleanly and reports it.
// A frame processed without fault ends the run of consecutive faults.
// ROS-free; owned and called by one thread (the nodelet's worker).
#pragma once

#include "hapi_eskf/covariance/storage_settings.hpp"

namespace hapi_eskf {

enum class FaultAction { kRestart, kFallBackToCpu, kStop };
const char* toString(FaultAction a);

class BackendFaultPolicy {
 public:
  BackendFaultPolicy(bool allow_cpu_fallback, int max_restarts = 2)
      : allow_cpu_fallback_(allow_cpu_fallback), max_restarts_(max_restarts) {}

  // A frame failed with kBackendError on a backend of kind `kind`.
  FaultAction onFault(BackendKind kind);
  // The replacement backend of kind `kind` could not be created.
  FaultAction onCreateFailed(BackendKind kind) const;
  // A frame was processed without a backend fault.
  void onSuccess() { consecutive_ = 0; }

  int consecutiveFaults() const { return consecutive_; }

 private:
  FaultAction giveUp(BackendKind kind) const;

  bool allow_cpu_fallback_;
  int max_restarts_;
  int consecutive_ = 0;
};

}  // namespace hapi_eskf
