// Result codes of every filter operation. The filter never throws on bad
// input: it returns one of these and leaves its state unchanged, so the ROS
// layer can count and report the rejection without the filter being corrupted.
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
  kNotInitialised,       // no valid state yet: the filter was never reset successfully
                         // (invalid settings, backend capacity mismatch) or a pose copy
                         // was never based on the filter
  kAwaitingImu,          // inertial model: not yet aligned to gravity (alignment_window of IMU
                         // samples needed first); frames before that are not processed
  kBackendUnavailable,   // no backend: none given, CUDA requested but no device / not compiled
  kBackendError,         // a CUDA / cuBLAS / cuSOLVER call failed
};

const char* toString(Status s);

}  // namespace hapi_eskf
