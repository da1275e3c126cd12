// Identity measure between two ORB results (CPU reference vs GPU), used by
// the identity test and printed by the benchmark.
#pragma once

#include "hapi_frontend/orb_core.hpp"

#include <algorithm>
#include <cstring>

namespace hapi_frontend {
namespace gpu_test {

struct OrbIdentity {
  int n_ref = 0, n_test = 0;
  int identical = 0;  // same index, same keypoint fields, same 32 descriptor bytes
  double percent() const {
    const int n = std::max(n_ref, n_test);
    return n == 0 ? 100.0 : 100.0 * identical / n;
  }
};

inline bool sameKeypoint(const OrbKeypoint& a, const OrbKeypoint& b) {
  return a.lx == b.lx && a.ly == b.ly && a.level == b.level && a.score == b.score && a.angle_bin == b.angle_bin &&
         a.x == b.x && a.y == b.y && a.size == b.size && a.angle == b.angle;
}

// Element-wise (the output order is part of the contract).
inline OrbIdentity compareOrb(const OrbResult& ref, const OrbResult& test) {
  OrbIdentity r;
  r.n_ref = static_cast<int>(ref.keypoints.size());
  r.n_test = static_cast<int>(test.keypoints.size());
  const int n = std::min(r.n_ref, r.n_test);
  for (int i = 0; i < n; ++i) {
    if (sameKeypoint(ref.keypoints[i], test.keypoints[i]) &&
        std::memcmp(&ref.descriptors[static_cast<size_t>(i) * kOrbDescBytes],
                    &test.descriptors[static_cast<size_t>(i) * kOrbDescBytes], kOrbDescBytes) == 0)
      ++r.identical;
  }
  return r;
}

}  // namespace gpu_test
}  // namespace hapi_frontend
