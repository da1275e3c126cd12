// Identity measure between two ORB results (CPU reference vs GPU), used by
// the identity test and printed by the benchmark.
#pragma once

#include "hapi_frontend/orb_core.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <tuple>

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

// Diagnosis of a mismatch: pairs keypoints by (level, lx, ly) and counts
// which fields differ; returns a one-line summary plus the first differences.
inline std::string diagnoseOrb(const OrbResult& ref, const OrbResult& test) {
  std::map<std::tuple<int, int, int>, int> pos;
  for (size_t i = 0; i < test.keypoints.size(); ++i) {
    const OrbKeypoint& k = test.keypoints[i];
    pos[std::make_tuple(k.level, k.lx, k.ly)] = static_cast<int>(i);
  }
  int missing = 0, order = 0, score = 0, angle = 0, desc = 0, fl = 0;
  std::string first;
  for (size_t i = 0; i < ref.keypoints.size(); ++i) {
    const OrbKeypoint& a = ref.keypoints[i];
    const auto it = pos.find(std::make_tuple(a.level, a.lx, a.ly));
    if (it == pos.end()) {
      ++missing;
      continue;
    }
    const OrbKeypoint& b = test.keypoints[it->second];
    order += it->second != static_cast<int>(i);
    score += a.score != b.score;
    angle += a.angle_bin != b.angle_bin;
    fl += a.x != b.x || a.y != b.y || a.size != b.size || a.angle != b.angle;
    const bool dd = std::memcmp(&ref.descriptors[i * kOrbDescBytes], &test.descriptors[it->second * kOrbDescBytes],
                                kOrbDescBytes) != 0;
    desc += dd;
    if ((dd || a.angle_bin != b.angle_bin || a.score != b.score) && first.size() < 600) {
      char buf[200];
      std::snprintf(buf, sizeof(buf), "\n  #%zu L%d (%d,%d) s%d/%d bin%d/%d desc0 %02x%02x%02x%02x/%02x%02x%02x%02x", i,
                    a.level, a.lx, a.ly, a.score, b.score, a.angle_bin, b.angle_bin, ref.descriptors[i * 32],
                    ref.descriptors[i * 32 + 1], ref.descriptors[i * 32 + 2], ref.descriptors[i * 32 + 3],
                    test.descriptors[it->second * 32], test.descriptors[it->second * 32 + 1],
                    test.descriptors[it->second * 32 + 2], test.descriptors[it->second * 32 + 3]);
      first += buf;
    }
  }
  char head[200];
  std::snprintf(head, sizeof(head), "ref %zu test %zu: missing %d, other index %d, score %d, angle %d, float %d, desc %d",
                ref.keypoints.size(), test.keypoints.size(), missing, order, score, angle, fl, desc);
  return head + first;
}

}  // namespace gpu_test
}  // namespace hapi_frontend
