#include "hapi_eskf/surface_motion/surface_motion_settings.hpp"

#include "hapi_eskf/settings_table.hpp"

namespace hapi_eskf {
namespace surface_motion {

std::string SurfaceMotionSettings::validate() const {
  const std::string e = fieldRangeError(*this);
  if (!e.empty()) return e;
  if (max_search_radius < search_radius) return "max_search_radius must be >= search_radius";
  if (max_flow_interval <= min_flow_interval) return "max_flow_interval must be > min_flow_interval";
  if (twist_average_window >= history_length) return "twist_average_window must be < history_length";
  return "";
}

}  // namespace surface_motion
}  // namespace hapi_eskf
