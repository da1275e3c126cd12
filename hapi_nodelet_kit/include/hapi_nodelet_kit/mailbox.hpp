// Mailbox<T>: the one-slot hand-over between a ROS callback and the worker
// thread of a HAPI nodelet. ROS-free, header-only.
//
// Why newest wins: the nodelets run on the nodelet manager's shared callback
// threads. A callback that waited for a slow worker would hold a thread other
// nodelets need and let the ROS queue fill with stale messages; instead the
// callback only put()s, an untaken older message is replaced (a frame that is
// already late is worth less than the current one) and the replacement is
// counted, so a worker that cannot keep up shows as drops, not as latency.
//
// API (thread-safe, the mailbox owns its lock):
//   bool put(T)                      post; true when it replaced an untaken
//                                    value (one drop, counted in dropped())
//   std::optional<T> take()          wait for a value; empty once closed
//   std::optional<T> take(timeout)   same, also empty after `timeout`
//   void close()                     wake every waiter; later put()s are
//                                    ignored, a pending value is discarded
//   bool closed(), uint64_t dropped()
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

namespace hapi_nodelet_kit {

template <typename T>
class Mailbox {
 public:
  // Returns true when an untaken value was overwritten (it is dropped and
  // counted). After close() the value is discarded and false is returned.
  bool put(T value) {
    bool replaced = false;
    {
      std::lock_guard<std::mutex> lk(mu_);
      if (closed_) return false;
      replaced = slot_.has_value();
      if (replaced) ++dropped_;
      slot_ = std::move(value);
    }
    cv_.notify_one();
    return replaced;
  }

  // Waits until a value is posted or the mailbox is closed. Empty once
  // closed, even with a value pending: a nodelet being unloaded must not
  // process one more frame first.
  std::optional<T> take() {
    std::unique_lock<std::mutex> lk(mu_);
    cv_.wait(lk, [&] { return slot_.has_value() || closed_; });
    return pop();
  }

  // As take(), but also returns empty when nothing arrived within `timeout`
  // (a worker with periodic duties of its own wakes up regularly).
  std::optional<T> take(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lk(mu_);
    cv_.wait_for(lk, timeout, [&] { return slot_.has_value() || closed_; });
    return pop();
  }

  void close() {
    {
      std::lock_guard<std::mutex> lk(mu_);
      closed_ = true;
      slot_.reset();
    }
    cv_.notify_all();
  }

  bool closed() const {
    std::lock_guard<std::mutex> lk(mu_);
    return closed_;
  }

  // Values replaced before they were taken, since construction.
  std::uint64_t dropped() const {
    std::lock_guard<std::mutex> lk(mu_);
    return dropped_;
  }

 private:
  std::optional<T> pop() {  // with mu_ held
    std::optional<T> out;
    if (!closed_ && slot_) {
      out = std::move(slot_);
      slot_.reset();
    }
    return out;
  }

  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::optional<T> slot_;
  bool closed_ = false;
  std::uint64_t dropped_ = 0;
};

}  // namespace hapi_nodelet_kit
