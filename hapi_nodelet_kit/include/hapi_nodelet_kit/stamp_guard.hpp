// StampGuard: the backwards-stamp rule of every HAPI nodelet, and the one
// parameter that configures it, ~time_jump_reset. ROS-free.
//
// A message whose stamp is not newer than the last accepted one is either
//  * a small step back (reordered or duplicated message): REJECTED, because
//    processing it would predict backwards in time or use a measurement twice;
//  * a step back by MORE than time_jump_reset seconds: a time jump (bag loop,
//    simulator or clock restart). The new timeline is ACCEPTED and the caller
//    RESETS whatever state belongs to the old one (the ES-EKF its filter; the
//    front end has no temporal state and only counts the reset).
// A stamp equal to the last accepted one is a step back of 0 s: rejected.
// Stamps going forward are always accepted; a forward jump is not a reset.
//
// Stamps are integer nanoseconds (ros::Time::toNSec()): exact, so two
// stamps 1 ns apart are never rounded into "equal".
//
// API:
//   TimeJumpResetParam::kName / kDefault / check(seconds)   the parameter
//   StampGuard guard(seconds);  guard.check(stamp_ns) -> StampCheck
//   StampCheck{verdict, previous_ns, back_ns}; StampVerdict kAccept/kReject/kReset
//   readTimeJumpReset(reader, ...) (time_jump_reset_param.hpp) reads the
//   parameter through a ParamReader.
#pragma once

#include "hapi_nodelet_kit/number_range.hpp"

#include <cstdint>
#include <mutex>
#include <string>

namespace hapi_nodelet_kit {

// The guard's private parameter, the same name in every nodelet.
struct TimeJumpResetParam {
  static constexpr const char* kName = "time_jump_reset";
  static constexpr double kDefault = 1.0;  // [s]
  // Allowed values [s]. 0 is allowed: every step back then resets and only
  // repeated stamps are rejected.
  static constexpr NumberRange kRange = NumberRange::atLeast(0.0);
  // Empty when `seconds` is allowed, else a message naming ~time_jump_reset
  // and its range.
  static std::string check(double seconds);
};

enum class StampVerdict { kAccept, kReject, kReset };
const char* toString(StampVerdict v);

struct StampCheck {
  StampVerdict verdict = StampVerdict::kAccept;
  bool had_previous = false;   // false for the first stamp (or after clear())
  std::int64_t previous_ns = 0;  // last accepted stamp before this check
  std::int64_t back_ns = 0;      // previous_ns - stamp when the stamp went back, else 0
  double backSec() const { return static_cast<double>(back_ns) * 1e-9; }
  double previousSec() const { return static_cast<double>(previous_ns) * 1e-9; }
};

// Thread-safe (owns its lock): callbacks on several manager threads may check.
class StampGuard {
 public:
  // Throws std::invalid_argument when TimeJumpResetParam::check() rejects it.
  explicit StampGuard(double time_jump_reset_s);

  // Classifies `stamp_ns` against the last accepted stamp; kAccept and kReset
  // make it the new last accepted stamp, kReject leaves the guard unchanged.
  StampCheck check(std::int64_t stamp_ns);

  // Forget the last stamp (after an explicit reset of the caller's state).
  void clear();

  double timeJumpResetSec() const { return jump_s_; }

 private:
  const double jump_s_;
  const std::int64_t jump_ns_;
  std::mutex mu_;
  bool has_last_ = false;
  std::int64_t last_ns_ = 0;
};

}  // namespace hapi_nodelet_kit
