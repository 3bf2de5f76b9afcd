// The directory heartbeat's timing (heartbeat_schedule.h), on fake time.

#include "heartbeat_schedule.h"

#include <gtest/gtest.h>

namespace ricochet::server::heartbeat_schedule_test {
namespace {

constexpr proto::TimeUs kSecond = proto::kMicrosPerSecond;

TEST(HeartbeatSchedule, BeatsOncePerPeriodOneAtATime) {
  HeartbeatSchedule beats(2 * kSecond, 10 * kSecond, 100 * kSecond);
  EXPECT_EQ(beats.next_at(), 100 * kSecond);
  EXPECT_FALSE(beats.start(100 * kSecond - 1));
  ASSERT_TRUE(beats.start(100 * kSecond));
  // In flight: no second beat, however late, and no deadline to wake for.
  EXPECT_FALSE(beats.start(110 * kSecond));
  EXPECT_EQ(beats.next_at(), std::nullopt);
  EXPECT_EQ(beats.finished(true, 100 * kSecond + 50'000), DirectoryListing::Listed);
  // The next one period after the last began, not after it came back.
  EXPECT_EQ(beats.next_at(), 102 * kSecond);
  EXPECT_FALSE(beats.start(102 * kSecond - 1));
  ASSERT_TRUE(beats.start(102 * kSecond));
  EXPECT_EQ(beats.finished(true, 102 * kSecond), DirectoryListing::Unchanged);
}

TEST(HeartbeatSchedule, ASlowWriteDelaysTheNextBeatInsteadOfQueueingBeats) {
  HeartbeatSchedule beats(2 * kSecond, 10 * kSecond, 0);
  ASSERT_TRUE(beats.start(0));
  EXPECT_EQ(beats.finished(true, 7 * kSecond), DirectoryListing::Listed);
  // Due since 2 s: one beat now, then one period on.
  ASSERT_TRUE(beats.start(7 * kSecond));
  EXPECT_FALSE(beats.start(7 * kSecond));
  beats.finished(true, 7 * kSecond);
  EXPECT_EQ(beats.next_at(), 9 * kSecond);
}

TEST(HeartbeatSchedule, AChangeOfMatchesBeatsSoonerButAtMostFourTimesAPeriod) {
  HeartbeatSchedule beats(4 * kSecond, 10 * kSecond, 0);
  ASSERT_TRUE(beats.start(0));
  beats.finished(true, 100'000);
  EXPECT_EQ(beats.next_at(), 4 * kSecond);
  beats.changed(3 * kSecond);  // a match ended: due now
  EXPECT_EQ(beats.next_at(), 3 * kSecond);
  ASSERT_TRUE(beats.start(3 * kSecond));
  // Another at once, while that one is in flight: due a quarter period after it began.
  beats.changed(3 * kSecond + 1);
  EXPECT_EQ(beats.next_at(), std::nullopt);
  beats.finished(true, 3 * kSecond + 2);
  EXPECT_EQ(beats.next_at(), 4 * kSecond);
  ASSERT_TRUE(beats.start(4 * kSecond));
  beats.finished(true, 4 * kSecond);
  EXPECT_EQ(beats.next_at(), 8 * kSecond);  // no change since: the period again
  beats.stop();
  beats.changed(5 * kSecond);
  EXPECT_EQ(beats.next_at(), std::nullopt);
}

TEST(HeartbeatSchedule, FailedWritesAreRetriedAtThePaceAndReportTheRowLostPastTheTtl) {
  HeartbeatSchedule beats(2 * kSecond, 10 * kSecond, 0);
  ASSERT_TRUE(beats.start(0));
  ASSERT_EQ(beats.finished(true, 0), DirectoryListing::Listed);
  proto::TimeUs now = 0;
  for (int i = 0; i < 4; ++i) {  // 2, 4, 6, 8 s: failed, still listed (written at 0)
    now += 2 * kSecond;
    ASSERT_TRUE(beats.start(now));
    EXPECT_EQ(beats.finished(false, now), DirectoryListing::Unchanged) << now;
    EXPECT_TRUE(beats.listed(now));
  }
  now += 2 * kSecond;  // 10 s: the row written at 0 is as old as the TTL
  ASSERT_TRUE(beats.start(now));
  EXPECT_EQ(beats.finished(false, now), DirectoryListing::Lost);
  EXPECT_FALSE(beats.listed(now));
  now += 2 * kSecond;
  ASSERT_TRUE(beats.start(now));
  EXPECT_EQ(beats.finished(false, now), DirectoryListing::Unchanged);  // reported once
  now += 2 * kSecond;
  ASSERT_TRUE(beats.start(now));
  EXPECT_EQ(beats.finished(true, now), DirectoryListing::Listed);
  EXPECT_TRUE(beats.listed(now));
}

TEST(HeartbeatSchedule, StoppedIsFinal) {
  HeartbeatSchedule beats(2 * kSecond, 10 * kSecond, 0);
  ASSERT_TRUE(beats.start(0));
  beats.finished(true, 0);
  beats.stop();
  EXPECT_EQ(beats.next_at(), std::nullopt);
  EXPECT_FALSE(beats.start(100 * kSecond));
  EXPECT_FALSE(beats.listed(kSecond));
}

}  // namespace
}  // namespace ricochet::server::heartbeat_schedule_test
