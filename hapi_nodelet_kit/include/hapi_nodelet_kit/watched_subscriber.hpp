// WatchedSubscriber: a ros::Subscriber that is re-created when its messages
// stop while a publisher is connected (ResubscribeSchedule says when and
// why), e.g. a topic from another host during and after a link outage.
// Owns its lock: the timer thread replaces the subscriber while callbacks
// and the owner's shutdown may run on other threads.
//
// Use: start() with a factory that subscribes (the callback calls
// received() first), shutdown() before the callback's object goes.
#pragma once

#include "hapi_nodelet_kit/resubscribe_schedule.hpp"

#include <ros/ros.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace hapi_nodelet_kit {

class WatchedSubscriber {
 public:
  using Factory = std::function<ros::Subscriber()>;

  // Subscribes now; with timeout > 0 checks every timeout/4 s (steady clock).
  // `owner` prefixes the log lines (the nodelet's name).
  void start(ros::NodeHandle& nh, Factory subscribe, double timeout, double max_wait, const std::string& owner);
  // From the message callback: the topic is alive.
  void received() { last_message_ns_.store(nowNs(), std::memory_order_relaxed); }
  // Stops the timer and unsubscribes; no callback starts after this returns.
  void shutdown();

  std::uint64_t resubscriptions() const { return resubscriptions_.load(); }
  std::string topic() const;

 private:
  static std::int64_t nowNs();
  void check();

  mutable std::mutex mu_;  // sub_, schedule_, subscribe_
  ros::Subscriber sub_;
  Factory subscribe_;
  ResubscribeSchedule schedule_{0, 0};
  ros::SteadyTimer timer_;
  std::string owner_;
  std::atomic<std::int64_t> last_message_ns_{-1};  // steady ns; -1: none yet
  std::atomic<std::uint64_t> resubscriptions_{0};
};

}  // namespace hapi_nodelet_kit
