// The re-subscription rule (resubscribe_schedule.hpp).
#include "hapi_nodelet_kit/resubscribe_schedule.hpp"

#include <gtest/gtest.h>

#include <vector>

using hapi_nodelet_kit::ResubscribeSchedule;

TEST(ResubscribeSchedule, DueAfterTimeoutOfSilenceOnlyWithAPublisher) {
  ResubscribeSchedule s(5.0, 20.0);
  EXPECT_FALSE(s.due(104.9, 100.0, true));
  EXPECT_TRUE(s.due(105.0, 100.0, true));
  EXPECT_FALSE(s.due(200.0, 100.0, false));  // nobody connected: nothing to reconnect to
}

TEST(ResubscribeSchedule, AStallGoesOnWithoutAConnectedPublisher) {
  // The new subscription cannot connect while the link is down (roscpp then
  // counts no publisher): the retries go on until a message arrives.
  ResubscribeSchedule s(5.0, 20.0);
  ASSERT_TRUE(s.due(5.0, 0.0, true));
  s.resubscribed(5.0);
  EXPECT_FALSE(s.due(14.0, 0.0, false));
  EXPECT_TRUE(s.due(15.0, 0.0, false));
  s.resubscribed(15.0);
  EXPECT_FALSE(s.due(40.0, 36.0, false));  // a message at 36 s ended the stall
}

TEST(ResubscribeSchedule, SilenceBacksOffToMaxWaitAndAMessageRestartsIt) {
  ResubscribeSchedule s(5.0, 20.0);
  const double last = 0.0;
  // A 30 s outage: re-subscriptions at 5, 15 (5 + 10) and 35 (15 + 20) s.
  std::vector<double> at;
  for (double t = 0; t <= 100.0; t += 0.25)
    if (s.due(t, last, true)) {
      at.push_back(t);
      s.resubscribed(t);
    }
  ASSERT_GE(at.size(), 5u);
  EXPECT_DOUBLE_EQ(at[0], 5.0);
  EXPECT_DOUBLE_EQ(at[1], 15.0);
  EXPECT_DOUBLE_EQ(at[2], 35.0);
  EXPECT_DOUBLE_EQ(at[3], 55.0);  // capped at max_wait
  EXPECT_DOUBLE_EQ(s.currentWait(), 20.0);
  // Traffic again at 101 s: the next stall starts with the timeout.
  EXPECT_FALSE(s.due(102.0, 101.0, true));
  EXPECT_DOUBLE_EQ(s.currentWait(), 5.0);
  EXPECT_TRUE(s.due(106.0, 101.0, true));
}

TEST(ResubscribeSchedule, ATopicThatNeverDeliveredIsNotWatched) {
  ResubscribeSchedule s(5.0, 10.0);
  EXPECT_FALSE(s.due(1e6, -1.0, true));
}

TEST(ResubscribeSchedule, ZeroTimeoutNeverResubscribes) {
  ResubscribeSchedule s(0.0, 0.0);
  EXPECT_FALSE(s.due(1e6, 0.0, true));
}
