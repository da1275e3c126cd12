// What the CPU benchmarks share: the calling thread's CPU time and the
// median of a sample.
#pragma once

#include <time.h>

#include <algorithm>
#include <vector>

namespace hapi_frontend_bench {

// CPU time of this thread [ms]: on a shared machine, wall time includes the
// time other processes hold the core; thread CPU time does not.
inline double threadCpuMs() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

inline double med(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace hapi_frontend_bench
