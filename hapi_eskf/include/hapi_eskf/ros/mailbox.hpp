// Single-slot "newest wins" mailbox: the ROS callback thread put()s, the worker
// thread take()s. A put() over an untaken message drops the old one and counts it.
#pragma once
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

namespace hapi_eskf {
namespace ros_glue {

template <typename T>
class Mailbox {
 public:
  /// Returns true when an untaken message was overwritten (dropped).
  bool put(T value) {
    bool dropped = false;
    {
      std::lock_guard<std::mutex> lk(mu_);
      dropped = slot_.has_value();
      if (dropped) ++dropped_;
      slot_ = std::move(value);
    }
    cv_.notify_one();
    return dropped;
  }
  /// Waits up to `timeout` for a message; empty when none or closed.
  std::optional<T> take(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lk(mu_);
    cv_.wait_for(lk, timeout, [&] { return slot_.has_value() || closed_; });
    std::optional<T> out;
    if (slot_) { out = std::move(slot_); slot_.reset(); }
    return out;
  }
  void close() {
    { std::lock_guard<std::mutex> lk(mu_); closed_ = true; }
    cv_.notify_all();
  }
  bool closed() const { std::lock_guard<std::mutex> lk(mu_); return closed_; }
  std::uint64_t dropped() const { std::lock_guard<std::mutex> lk(mu_); return dropped_; }

 private:
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::optional<T> slot_;
  bool closed_ = false;
  std::uint64_t dropped_ = 0;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
