// The one input check of a StereoFrame, run by every back end before any
// state changes (the ES-EKF and the associating back ends alike).
#pragma once

#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

namespace hapi_eskf {

// kNonFinite (stamp, z, C_z, response), kInvalidArgument (stamp before
// `time`, descriptor length or size), kEmptyInput (no measurements),
// kCapacityExceeded (more than `max_measurements`), kDuplicateId (a front-end
// id twice), kNotPositiveDefinite (a C_z).
Status checkStereoFrame(const StereoFrame& frame, double time, int descriptor_length, int max_measurements);

}  // namespace hapi_eskf
