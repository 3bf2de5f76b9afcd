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

TEST(RefusalPolicy, PlacementFindsAgainOnASpentTicketWaitsOnAFullFleetAndStopsOnAnUnknownMode) {
  for (const wire::ErrorCode code : {wire::MATCH_FULL, wire::UNKNOWN_TICKET, wire::EXPIRED_TICKET,
                                     wire::MATCH_NOT_FOUND, wire::ADDRESS_SEAT_LIMIT}) {
    EXPECT_EQ(placement_action(code), PlacementAction::FindAgain) << wire::ErrorCode_Name(code);
  }
  for (const wire::ErrorCode code :
       {wire::NO_SERVER_AVAILABLE, wire::FIND_MATCH_RATE_LIMITED, wire::SERVER_BUSY}) {
    EXPECT_EQ(placement_action(code), PlacementAction::RetryLater) << wire::ErrorCode_Name(code);
  }
  EXPECT_EQ(placement_action(wire::UNKNOWN_MODE_OR_MAP), PlacementAction::GiveUp);
  EXPECT_EQ(placement_action(wire::INVALID_REQUEST), PlacementAction::GiveUp);
  for (const wire::ErrorCode code : {wire::INTERNAL, wire::WRONG_STATE, wire::SHUTTING_DOWN}) {
    EXPECT_EQ(placement_action(code), PlacementAction::FailedAttempt) << wire::ErrorCode_Name(code);
  }
  // Once find_match's burst is spent, its rate is one every 2 s: the retry waits about that.
  EXPECT_DOUBLE_EQ(retry_later_s(0.5), 2.0);
  EXPECT_DOUBLE_EQ(retry_later_s(0.0), 1.0);
  EXPECT_NEAR(retry_later_s(0.999), 2.998, 1e-9);
  EXPECT_DOUBLE_EQ(retry_later_s(7.0), 3.0);  // out of range: clamped
  static_assert(kMaxFindAgainInARow >= 3 && kMaxFindAgainInARow <= 20);
  // A refused ticket: find again soon (the next heartbeat shows the seats anew), never over 3 s.
  EXPECT_DOUBLE_EQ(find_again_s(1, 0.5), 0.25);
  EXPECT_DOUBLE_EQ(find_again_s(2, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(find_again_s(4, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(find_again_s(kMaxFindAgainInARow, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(find_again_s(1, 0.0), 0.125);
  EXPECT_NEAR(find_again_s(9, 0.999), 2.998, 1e-9);
}

}  // namespace
}  // namespace ricochet::bot::refusal_policy_test
