// Result codes of every filter operation. The filter never throws on bad
// input: it returns one of these and leaves its state unchanged, so the ROS
// layer can count and report the rejection (brief: "never corrupts the filter").
#pragma once

namespace hapi_eskf {

enum class Status : int {
  kOk = 0,
  kEmptyInput,           // no measurements / nothing to do where something was required
  kNonFinite,            // NaN or Inf in a measurement, covariance or time step
  kDuplicateId,          // the same landmark slot or measurement used twice in one call
  kCapacityExceeded,     // more landmarks / measurements than the configured capacity
  kNotPositiveDefinite,  // innovation covariance S (or a measurement covariance) not PD
  kInvalidArgument,      // bad index, bad size, negative dt, inconsistent lengths ...
  kBackendUnavailable,   // e.g. CUDA requested but no device / not compiled
  kBackendError,         // a CUDA / cuBLAS / cuSOLVER call failed
};

const char* toString(Status s);

}  // namespace hapi_eskf
