// The CPU reference of the block matcher (dense_depth_block_match.hpp).
#include "hapi_surface/dense_depth_block_match.hpp"

namespace hapi_surface {

void blockMatchCpu(const std::uint8_t* left, const std::uint8_t* right, int w, int h, int stride,
                   const BlockMatchParams& p, float* disparity) {
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      disparity[static_cast<std::int64_t>(y) * w + x] =
          block_match_detail::matchPixel(left, right, w, h, stride, x, y, p);
}

}  // namespace hapi_surface
