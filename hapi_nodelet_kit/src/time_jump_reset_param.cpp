// readTimeJumpReset (time_jump_reset_param.hpp).
#include "hapi_nodelet_kit/time_jump_reset_param.hpp"

#include "hapi_nodelet_kit/stamp_guard.hpp"

namespace hapi_nodelet_kit {

double readTimeJumpReset(ParamReader& reader, const std::string& deprecated_name) {
  double s = TimeJumpResetParam::kDefault;
  if (deprecated_name.empty())
    reader.read(TimeJumpResetParam::kName, &s);
  else
    reader.readRenamed(TimeJumpResetParam::kName, deprecated_name, &s);
  const std::string why = TimeJumpResetParam::check(s);
  if (!why.empty()) {
    reader.error(why);
    s = TimeJumpResetParam::kDefault;  // never hand an invalid value on
  }
  return s;
}

}  // namespace hapi_nodelet_kit
