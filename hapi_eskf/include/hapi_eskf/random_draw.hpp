// drawVec3: a 3-vector of three draws of one distribution, in a fixed order.
//
// Why: in Vec3(d(rng), d(rng), d(rng)) the order of the three calls is
// unspecified (gcc evaluates the arguments right to left, clang left to
// right), so the same seed gives another sample with another compiler. Every
// simulation, test, tool and benchmark of hapi_eskf draws vectors through
// this, so a seed means the same data everywhere. The order is gcc's (z
// first), the compiler every recorded figure was made with.
#pragma once

#include "hapi_eskf/types.hpp"

namespace hapi_eskf {

template <class Distribution, class Engine>
Vec3 drawVec3(Distribution& d, Engine& rng) {
  const double z = d(rng);
  const double y = d(rng);
  const double x = d(rng);
  return Vec3(x, y, z);
}

}  // namespace hapi_eskf
