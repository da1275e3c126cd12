// ResubscribeSchedule: when a subscription whose messages stopped while its
// publisher is still registered is re-created. ROS-free (times in seconds of
// a steady clock); WatchedSubscriber (watched_subscriber.hpp) applies it.
//
// Why: ROS 1 topics between hosts are TCP connections. When the link drops
// packets for a while (a WiFi outage), TCP retransmits with exponential
// backoff (RTO doubling to 120 s) and roscpp never notices a stalled
// connection, only a closed one: after a 30 s outage the next retransmission
// may come 20-30 s after the link is back. A new subscription opens a new
// connection, which carries data as soon as the link does.
//
// Rule: a stall starts when a topic that delivered messages has had none
// for `timeout` seconds while a publisher is connected; a re-subscription is
// then due. A topic that never delivered is not watched (roscpp connects it
// itself, and a re-subscription loses what is published while it
// reconnects: a publisher that is connected but has not started yet must not
// pay for that). It stays a stall,
// with further re-subscriptions, until a message arrives, whether or not the
// new subscription has connected (during an outage it cannot). The wait
// since the last message or re-subscription, whichever is later, starts at
// `timeout` and doubles after each re-subscription, up to `max_wait`, so a
// publisher that is merely idle (a paused bag) costs one re-subscription
// every max_wait seconds; any message ends the stall. Without a connected
// publisher and outside a stall nothing is due: roscpp itself connects to
// publishers that appear later. timeout 0 disables the rule.
#pragma once

namespace hapi_nodelet_kit {

class ResubscribeSchedule {
 public:
  ResubscribeSchedule(double timeout, double max_wait);

  // `last_message`: steady time of the newest message, negative when none
  // came yet. Pure check; the caller acts and calls resubscribed().
  bool due(double now, double last_message, bool publisher_connected);
  void resubscribed(double now);

  double timeout() const { return timeout_; }
  double currentWait() const { return wait_; }

 private:
  double timeout_, max_wait_, wait_;
  double last_resubscribe_ = -1e300;
};

}  // namespace hapi_nodelet_kit
