// Issue 29: a bot gave up on SERVER_BUSY at sign-in and counted ADDRESS_SEAT_LIMIT as a failed
// attempt; both are the server working as meant.
#include "ricochet/bot/refusal_policy.h"

#include <gtest/gtest.h>

namespace ricochet::bot::refusal_policy_test {
namespace {

TEST(RefusalPolicy, ABusyServerIsRetriedAndAFullOneWaitedForNeitherCountsAsAFailure) {
  EXPECT_EQ(refusal_action(wire::SERVER_BUSY), RefusalAction::Retry);
  EXPECT_EQ(refusal_action(wire::ADDRESS_SEAT_LIMIT), RefusalAction::WaitForRoom);
  EXPECT_EQ(refusal_action(wire::MATCH_FULL), RefusalAction::WaitForRoom);
  for (const wire::ErrorCode code :
       {wire::LOGIN_RATE_LIMITED, wire::INTERNAL, wire::RATE_LIMITED, wire::CREATE_RATE_LIMITED}) {
    EXPECT_EQ(refusal_action(code), RefusalAction::FailedAttempt) << wire::ErrorCode_Name(code);
  }
}

TEST(RefusalPolicy, BusyBackOffDoublesToEightSecondsAndSpreadsTheBots) {
  EXPECT_DOUBLE_EQ(busy_backoff_s(1, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(busy_backoff_s(2, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(busy_backoff_s(5, 0.5), 8.0);
  EXPECT_DOUBLE_EQ(busy_backoff_s(40, 0.5), 8.0);
  EXPECT_DOUBLE_EQ(busy_backoff_s(3, 0.0), 1.0);       // half
  EXPECT_NEAR(busy_backoff_s(3, 0.999), 2.998, 1e-9);  // up to one and a half
  EXPECT_DOUBLE_EQ(busy_backoff_s(0, 0.5), 0.5);       // out of range: the first
}

}  // namespace
}  // namespace ricochet::bot::refusal_policy_test
