// WatchedSubscriber (watched_subscriber.hpp).
#include "hapi_nodelet_kit/watched_subscriber.hpp"

#include <chrono>

namespace hapi_nodelet_kit {

std::int64_t WatchedSubscriber::nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void WatchedSubscriber::start(ros::NodeHandle& nh, Factory subscribe, double timeout, double max_wait,
                              const std::string& owner) {
  std::lock_guard<std::mutex> lk(mu_);
  owner_ = owner;
  subscribe_ = std::move(subscribe);
  schedule_ = ResubscribeSchedule(timeout, max_wait);
  last_message_ns_ = -1;  // nothing received yet: not watched
  sub_ = subscribe_();
  if (timeout > 0)
    timer_ = nh.createSteadyTimer(ros::WallDuration(timeout / 4), [this](const ros::SteadyTimerEvent&) { check(); });
}

void WatchedSubscriber::shutdown() {
  timer_.stop();  // waits for a running check()
  std::lock_guard<std::mutex> lk(mu_);
  sub_.shutdown();
}

std::string WatchedSubscriber::topic() const {
  std::lock_guard<std::mutex> lk(mu_);
  return sub_.getTopic();
}

void WatchedSubscriber::check() {
  std::lock_guard<std::mutex> lk(mu_);
  if (!sub_) return;  // shut down
  const double now = nowNs() * 1e-9;
  const std::int64_t last_ns = last_message_ns_.load(std::memory_order_relaxed);
  const double last = last_ns < 0 ? -1.0 : last_ns * 1e-9;
  if (!schedule_.due(now, last, sub_.getNumPublishers() > 0)) return;
  const bool first = schedule_.currentWait() <= schedule_.timeout();
  const std::string topic = sub_.getTopic();
  // (getNumPublishers counts connected publishers, not registered ones.)
  // One warning per stall; the backed-off retries of an idle publisher are
  // debug output.
  if (first) {
    ROS_WARN("%s: no message on %s for %.1f s although it has %u publisher(s): re-subscribing (a connection "
             "stalled by a link outage would otherwise resume only at TCP's next retransmission; retried until "
             "a message arrives)",
             owner_.c_str(), topic.c_str(), now - last, sub_.getNumPublishers());
  } else {
    ROS_DEBUG("%s: still no message on %s after %.1f s: re-subscribing", owner_.c_str(), topic.c_str(), now - last);
  }
  // The old subscription (and its connections) goes first, so the new one
  // is not merged into it by roscpp's per-topic subscription.
  sub_.shutdown();
  sub_ = subscribe_();
  schedule_.resubscribed(now);
  ++resubscriptions_;
}

}  // namespace hapi_nodelet_kit
