// The token bucket on fake time: a full burst at once, refills at the rate up to the burst,
// and time running backwards refills nothing.
#include "ricochet/proto/token_bucket.h"

#include <gtest/gtest.h>

namespace ricochet::proto::token_bucket_test {
namespace {

constexpr TimeUs kStart = 5 * kMicrosPerSecond;

int taken_at(TokenBucket& bucket, TimeUs now, int tries) {
  int taken = 0;
  for (int i = 0; i < tries; ++i) taken += bucket.take(now);
  return taken;
}

TEST(TokenBucket, AFreshBucketGivesItsBurstAtOnceThenNothing) {
  TokenBucket bucket(2.0, 3.0, kStart);
  EXPECT_TRUE(bucket.full(kStart));
  EXPECT_EQ(taken_at(bucket, kStart, 10), 3);
  EXPECT_FALSE(bucket.full(kStart));
  EXPECT_FALSE(bucket.take(kStart));
}

TEST(TokenBucket, RefillsAtItsRate) {
  TokenBucket bucket(2.0, 3.0, kStart);
  EXPECT_EQ(taken_at(bucket, kStart, 3), 3);
  // 2 per second: one token every 500 ms, not a microsecond earlier.
  EXPECT_FALSE(bucket.take(kStart + 500 * kMicrosPerMilli - 1));
  EXPECT_TRUE(bucket.take(kStart + 500 * kMicrosPerMilli));
  EXPECT_FALSE(bucket.take(kStart + 500 * kMicrosPerMilli));
  EXPECT_EQ(taken_at(bucket, kStart + 1500 * kMicrosPerMilli, 10), 2);
}

TEST(TokenBucket, RefillsNoFurtherThanTheBurst) {
  TokenBucket bucket(10.0, 4.0, kStart);
  EXPECT_EQ(taken_at(bucket, kStart, 4), 4);
  const TimeUs hour_later = kStart + 3600 * kMicrosPerSecond;
  EXPECT_TRUE(bucket.full(hour_later));
  EXPECT_EQ(taken_at(bucket, hour_later, 10), 4);
}

TEST(TokenBucket, TimeRunningBackwardsRefillsNothing) {
  TokenBucket bucket(1.0, 1.0, kStart);
  EXPECT_TRUE(bucket.take(kStart + 2 * kMicrosPerSecond));
  EXPECT_FALSE(bucket.take(kStart));  // an earlier `now` is not a refill
  EXPECT_FALSE(bucket.take(kStart + 2 * kMicrosPerSecond));
  EXPECT_TRUE(bucket.take(kStart + 3 * kMicrosPerSecond));
}

TEST(TokenBucket, AvailableSaysWhetherTakeWouldSucceedAndTakesNothing) {
  TokenBucket bucket(1.0, 2.0, kStart);
  EXPECT_TRUE(bucket.available(kStart));
  EXPECT_TRUE(bucket.available(kStart));
  EXPECT_TRUE(bucket.take(kStart));
  EXPECT_TRUE(bucket.take(kStart));
  EXPECT_FALSE(bucket.available(kStart));
  EXPECT_TRUE(bucket.available(kStart + kMicrosPerSecond));
}

TEST(TokenBucket, AFractionalRateAccumulatesAcrossCalls) {
  TokenBucket bucket(0.5, 1.0, kStart);
  EXPECT_TRUE(bucket.take(kStart));
  EXPECT_FALSE(bucket.take(kStart + kMicrosPerSecond));  // half a token
  EXPECT_TRUE(bucket.take(kStart + 2 * kMicrosPerSecond));
}

}  // namespace
}  // namespace ricochet::proto::token_bucket_test
