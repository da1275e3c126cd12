// Reading ~time_jump_reset, the StampGuard's parameter (stamp_guard.hpp),
// through a ParamReader: the same name, default and range in every nodelet.
#pragma once

#include "hapi_nodelet_kit/param_reader.hpp"

#include <string>

namespace hapi_nodelet_kit {

// Reads ~time_jump_reset [s] (TimeJumpResetParam::kDefault when not set) and
// records an error in `reader` when it is outside TimeJumpResetParam::kRange.
// deprecated_name: an older name of the same parameter in this nodelet, still
// accepted with a warning (ParamReader::readRenamed); empty when none.
double readTimeJumpReset(ParamReader& reader, const std::string& deprecated_name = "");

}  // namespace hapi_nodelet_kit
