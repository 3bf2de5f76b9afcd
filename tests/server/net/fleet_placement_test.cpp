// What the control sessions use to place players (fleet_placement.h): the find_match limit per
// account on fake time, the ticket's two forms, and the claims in flight a heartbeat's
// counted_ms waits for (claims_in_flight.h).

#include "fleet_placement.h"

#include <gtest/gtest.h>

#include "enum_count.h"

namespace ricochet::server::fleet_placement_test {
namespace {

constexpr proto::TimeUs kSecond = proto::kMicrosPerSecond;

TEST(FindMatchLimiter, AnAccountGetsItsBurstThenTheRateAndOthersAreNotTouched) {
  FindMatchLimiter limiter(30);  // one every 2 s, bursts of 5
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(limiter.take(7, 0)) << i;
  EXPECT_FALSE(limiter.take(7, 0));
  EXPECT_TRUE(limiter.take(8, 0));  // another account
  EXPECT_FALSE(limiter.take(7, 2 * kSecond - 1));
  EXPECT_TRUE(limiter.take(7, 2 * kSecond));
  EXPECT_FALSE(limiter.take(7, 2 * kSecond));
}

TEST(FindMatchLimiter, ForgetsRefilledAccountsOnceManyAreTracked) {
  FindMatchLimiter limiter(30);
  for (std::uint64_t account = 1; account <= 5000; ++account) limiter.take(account, 0);
  EXPECT_EQ(limiter.tracked(), 5000u);
  // Ten seconds on, every bucket is full again: the next take prunes them all but its own.
  EXPECT_TRUE(limiter.take(1, 10 * kSecond));
  EXPECT_EQ(limiter.tracked(), 1u);
}

TEST(Ticket, IsThirtyTwoBytesOnTheWireAndSixtyFourHexDigitsInTheDatabase) {
  const std::string hex = "00ff10a0" + std::string(56, 'e');
  const std::string bytes = ticket_bytes(hex);
  ASSERT_EQ(bytes.size(), kTicketBytes);
  EXPECT_EQ(static_cast<unsigned char>(bytes[1]), 0xFF);
  EXPECT_EQ(ticket_hex(bytes), hex);
  EXPECT_EQ(ticket_hex(bytes.substr(1)), std::nullopt);
  EXPECT_EQ(ticket_hex(""), std::nullopt);
}

TEST(Placement, ServerIdsAreDrawnAndFitTheDirectory) {
  const std::string id = draw_server_id();
  EXPECT_EQ(id.size(), 19u);
  EXPECT_EQ(id.rfind("rs-", 0), 0u);
  EXPECT_NE(id, draw_server_id());
}

TEST(ClaimsInFlight, FiguresAreCountedAsOfTheOldestClaimStillInFlight) {
  db::UnixMillis now = 1'000;
  ClaimsInFlight claims([&now] { return now; });
  EXPECT_EQ(claims.counted_as_of(), 1'000);  // none in flight: now
  {
    const ClaimsInFlight::Claim first = claims.begin();
    EXPECT_EQ(first.claimed_ms(), 1'000);
    now = 1'010;
    {
      const ClaimsInFlight::Claim second = claims.begin();
      EXPECT_EQ(second.claimed_ms(), 1'010);
      now = 1'020;
      EXPECT_EQ(claims.counted_as_of(), 1'000);
      EXPECT_EQ(claims.in_flight(), 2u);
    }
    EXPECT_EQ(claims.counted_as_of(), 1'000);  // the first is still being seated
  }
  EXPECT_EQ(claims.in_flight(), 0u);
  EXPECT_EQ(claims.counted_as_of(), 1'020);
}

TEST(Placement, ResultAndOutcomeEnumsAreCounted) {
  ricochet::test::expect_counted<TicketResult>(kTicketResultCount, [](auto v) { return name(v); });
  ricochet::test::expect_counted<HeartbeatOutcome>(kHeartbeatOutcomeCount,
                                                   [](auto v) { return name(v); });
}

}  // namespace
}  // namespace ricochet::server::fleet_placement_test
