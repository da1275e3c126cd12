// hapi_sim: the one number format of every text file and YAML string the
// simulator writes (the shorter of %.15g and %.17g that reads back to the
// same double: exact, yet 0.045 stays "0.045") and the 4x4 row-major form of
// a pose.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <string>

#include "hapi_sim/globe_sim.hpp"

namespace hapi_sim {

inline std::string formatNumber(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// "a, b, ..., p" of the homogeneous matrix [R p; 0 0 0 1], row-major; rows
// separated by `row_sep` (", " for one line).
inline std::string formatMatrix4(const Pose& P, const std::string& row_sep = ", ") {
  const Eigen::Matrix3d R = P.q.toRotationMatrix();
  std::string s;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const double v = r < 3 ? (c < 3 ? R(r, c) : P.p[r]) : (c == 3 ? 1.0 : 0.0);
      s += formatNumber(v);
      if (c < 3) s += ", ";
    }
    if (r < 3) s += row_sep;
  }
  return s;
}

}  // namespace hapi_sim
