// Per-reason counters (reason -> count) in a diagnostic status: their total,
// and one "<prefix><reason>" entry each, the keys tests and operators read.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include <cstdint>
#include <map>
#include <string>

namespace hapi_frontend {

using ReasonCounters = std::map<std::string, std::uint64_t>;

inline std::uint64_t counterTotal(const ReasonCounters& counters) {
  std::uint64_t total = 0;
  for (const auto& kv : counters) total += kv.second;
  return total;
}

inline void addCounters(diagnostic_updater::DiagnosticStatusWrapper& stat, const std::string& prefix,
                        const ReasonCounters& counters) {
  for (const auto& kv : counters) stat.add(prefix + kv.first, kv.second);
}

}  // namespace hapi_frontend
