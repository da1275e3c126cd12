// The display colour of a projected value: the jet colour map as a 256-entry
// table, built once, and the value range it spans.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace hapi_surface {

using Rgb8 = std::array<std::uint8_t, 3>;

// Colour of `value` mapped linearly from [lo, hi] onto the table (clamped);
// NaN (no value) is mid grey.
Rgb8 jetColour(float value, float lo, float hi);

// The 1st and 99th percentiles of the finite values (lo == hi when fewer
// than two); false when there is none.
bool valueRange(const std::vector<float>& values, float* lo, float* hi);

}  // namespace hapi_surface
