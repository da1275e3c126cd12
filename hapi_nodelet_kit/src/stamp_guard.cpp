// The backwards-stamp rule (stamp_guard.hpp) and the range of ~time_jump_reset.
#include "hapi_nodelet_kit/stamp_guard.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hapi_nodelet_kit {

std::string TimeJumpResetParam::check(double seconds) {
  return outOfRange(std::string("~") + kName, kRange, "s", seconds);
}

const char* toString(StampVerdict v) {
  switch (v) {
    case StampVerdict::kAccept: return "accept";
    case StampVerdict::kReject: return "reject";
    case StampVerdict::kReset: return "reset";
  }
  return "unknown";
}

namespace {
std::int64_t toNs(double seconds) {
  const std::string why = TimeJumpResetParam::check(seconds);
  if (!why.empty()) throw std::invalid_argument("StampGuard: " + why);
  // Saturated: any threshold beyond ~292 years means "never a time jump".
  const double ns = seconds * 1e9;
  if (ns >= 9.2e18) return std::numeric_limits<std::int64_t>::max();
  return std::llround(ns);
}
}  // namespace

StampGuard::StampGuard(double time_jump_reset_s) : jump_s_(time_jump_reset_s), jump_ns_(toNs(time_jump_reset_s)) {}

StampCheck StampGuard::check(std::int64_t stamp_ns) {
  std::lock_guard<std::mutex> lk(mu_);
  StampCheck c;
  c.had_previous = has_last_;
  c.previous_ns = last_ns_;
  if (has_last_ && stamp_ns <= last_ns_) {
    c.back_ns = last_ns_ - stamp_ns;
    if (c.back_ns <= jump_ns_) {
      c.verdict = StampVerdict::kReject;
      return c;
    }
    c.verdict = StampVerdict::kReset;
  }
  has_last_ = true;
  last_ns_ = stamp_ns;
  return c;
}

void StampGuard::clear() {
  std::lock_guard<std::mutex> lk(mu_);
  has_last_ = false;
  last_ns_ = 0;
}

}  // namespace hapi_nodelet_kit
