#include "hapi_surface/dense_depth_settings.hpp"

#include <hapi_eskf/settings_table.hpp>

namespace hapi_surface {

std::string DenseDepthSettings::validate() const {
  const std::string e = hapi_eskf::fieldRangeError(*this);
  if (!e.empty()) return e;
  if (max_depth <= min_depth) return "max_depth must be > min_depth";
  if (block_size % 2 == 0) return "block_size must be odd";
  if (p2_per_pixel <= p1_per_pixel) return "p2_per_pixel must be > p1_per_pixel (OpenCV's SGBM requires P2 > P1)";
  return "";
}

}  // namespace hapi_surface
