// The re-subscription rule (resubscribe_schedule.hpp).
#include "hapi_nodelet_kit/resubscribe_schedule.hpp"

#include <algorithm>

namespace hapi_nodelet_kit {

ResubscribeSchedule::ResubscribeSchedule(double timeout, double max_wait)
    : timeout_(timeout), max_wait_(std::max(timeout, max_wait)), wait_(timeout) {}

bool ResubscribeSchedule::due(double now, double last_message, bool publisher_connected) {
  const bool in_stall = last_resubscribe_ >= last_message;
  if (!in_stall) wait_ = timeout_;  // traffic since the last re-subscription: a new stall starts over
  if (timeout_ <= 0 || last_message < 0 || (!publisher_connected && !in_stall)) return false;
  return now - std::max(last_message, last_resubscribe_) >= wait_;
}

void ResubscribeSchedule::resubscribed(double now) {
  last_resubscribe_ = now;
  wait_ = std::min(2 * wait_, max_wait_);
}

}  // namespace hapi_nodelet_kit
