// Rate limit of error logs per reason (not per call site like
// NODELET_ERROR_THROTTLE), so a flood of one kind of bad input never hides
// another kind. Thread-safe; wall clock (keeps working when simulated time
// pauses or jumps).
#pragma once

#include <ros/time.h>

#include <map>
#include <mutex>
#include <string>

namespace hapi_frontend {

class ReasonThrottle {
 public:
  explicit ReasonThrottle(double period_s) : period_s_(period_s) {}
  // true for the first call of a reason and then at most once a period.
  bool shouldLog(const std::string& reason) {
    const ros::WallTime now = ros::WallTime::now();
    std::lock_guard<std::mutex> lock(mutex_);
    ros::WallTime& last = last_[reason];
    if (!last.isZero() && (now - last).toSec() < period_s_) return false;
    last = now;
    return true;
  }

 private:
  const double period_s_;
  std::mutex mutex_;
  std::map<std::string, ros::WallTime> last_;
};

}  // namespace hapi_frontend
