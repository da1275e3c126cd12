// Mailbox<T>: newest wins, drops counted, close() wakes and empties.
#include "hapi_nodelet_kit/mailbox.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <thread>

using hapi_nodelet_kit::Mailbox;
using namespace std::chrono_literals;

TEST(Mailbox, NewestWinsAndReplacementsAreCounted) {
  Mailbox<int> box;
  EXPECT_FALSE(box.put(1));
  EXPECT_TRUE(box.put(2));  // 1 was never taken
  EXPECT_TRUE(box.put(3));
  EXPECT_EQ(box.dropped(), 2u);
  auto v = box.take(0ms);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(*v, 3);
  EXPECT_FALSE(box.take(0ms).has_value());  // taken: empty again
  EXPECT_FALSE(box.put(4));                 // nothing pending: no drop
  EXPECT_EQ(box.dropped(), 2u);
}

TEST(Mailbox, MoveOnlyValues) {
  Mailbox<std::unique_ptr<int>> box;
  box.put(std::make_unique<int>(7));
  auto v = box.take();
  ASSERT_TRUE(v && *v);
  EXPECT_EQ(**v, 7);
}

TEST(Mailbox, TakeWaitsForAPut) {
  Mailbox<int> box;
  std::thread producer([&] {
    std::this_thread::sleep_for(20ms);
    box.put(42);
  });
  auto v = box.take();
  producer.join();
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(*v, 42);
}

TEST(Mailbox, TimedTakeReturnsEmptyOnTimeout) {
  Mailbox<int> box;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(box.take(30ms).has_value());
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 30ms);
}

TEST(Mailbox, CloseWakesAWaiterAndDiscardsPendingAndLaterValues) {
  Mailbox<int> box;
  std::optional<int> got = 0;
  std::thread worker([&] { got = box.take(); });
  std::this_thread::sleep_for(20ms);
  box.close();
  worker.join();
  EXPECT_FALSE(got.has_value());
  EXPECT_TRUE(box.closed());
  EXPECT_FALSE(box.put(5));
  EXPECT_FALSE(box.take(0ms).has_value());

  Mailbox<int> pending;
  pending.put(1);
  pending.close();
  EXPECT_FALSE(pending.take().has_value());  // does not block, value discarded
  EXPECT_EQ(pending.dropped(), 0u);
}
