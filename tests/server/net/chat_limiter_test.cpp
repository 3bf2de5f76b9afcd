#include "chat_limiter.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace ricochet::server::chat_limiter_test {
namespace {

constexpr proto::TimeUs kSecond = proto::kMicrosPerSecond;

ChatLimits limits() {
  ChatLimits out;
  out.account_lines_per_s = 1;
  out.account_burst = 3;
  out.match_lines_per_s = 2;
  out.match_burst = 5;
  return out;
}

TEST(ChatLimiter, AnAccountGetsItsBurstThenItsRateWhateverItsSessions) {
  EpisodeLog episodes;
  ChatLimiter limiter(limits(), episodes);
  // However many sessions an account sends from, they all draw on the one bucket.
  for (int line = 0; line < 3; ++line) EXPECT_EQ(limiter.take(7, 1, 0), std::nullopt) << line;
  EXPECT_EQ(limiter.take(7, 1, 0), ChatLimit::Account);
  EXPECT_EQ(limiter.take(7, 1, kSecond / 2), ChatLimit::Account);
  EXPECT_EQ(limiter.take(7, 1, kSecond), std::nullopt) << "one line a second";
  EXPECT_EQ(limiter.refusals()[static_cast<std::size_t>(ChatLimit::Account)], 2u);
  EXPECT_EQ(episodes.open_episodes(kSecond), 1u) << "logged once, as one episode";
  EXPECT_NE(limiter.explain(ChatLimit::Account).find("1 line/s per account, bursts of 3"),
            std::string::npos)
      << limiter.explain(ChatLimit::Account);
}

TEST(ChatLimiter, AMatchCarriesItsLimitWhateverTheNumberOfAccounts) {
  EpisodeLog episodes;
  ChatLimiter limiter(limits(), episodes);
  int passed = 0;
  for (std::uint64_t account = 1; account <= 20; ++account) {
    if (!limiter.take(account, 4, 0)) ++passed;
  }
  EXPECT_EQ(passed, 5);
  EXPECT_EQ(limiter.refusals()[static_cast<std::size_t>(ChatLimit::Match)], 15u);
  EXPECT_EQ(limiter.take(21, 5, 0), std::nullopt) << "another match has its own";
  EXPECT_EQ(limiter.take(22, 4, kSecond / 2), std::nullopt) << "two lines a second";
  EXPECT_EQ(limiter.take(23, 4, kSecond / 2), ChatLimit::Match);
}

TEST(ChatLimiter, AnAccountQuietForAWhileHasItsWholeBurstAgain) {
  EpisodeLog episodes;
  ChatLimiter limiter(limits(), episodes);
  EXPECT_EQ(limiter.take(7, 1, 0), std::nullopt);
  EXPECT_EQ(limiter.take(7, 1, 0), std::nullopt);
  EXPECT_EQ(limiter.take(7, 1, 0), std::nullopt);
  EXPECT_EQ(limiter.take(7, 1, 0), ChatLimit::Account);
  // A minute later (the sweep forgot the full bucket: a fresh one is the same).
  for (int line = 0; line < 3; ++line) {
    EXPECT_EQ(limiter.take(7, 1, 60 * kSecond), std::nullopt) << line;
  }
}

TEST(ChatLimiter, RefusesLimitsOutOfRange) {
  EpisodeLog episodes;
  ChatLimits bad = limits();
  bad.account_lines_per_s = 0;
  EXPECT_THROW(ChatLimiter(bad, episodes), std::invalid_argument);
  bad = limits();
  bad.match_burst = 0;
  EXPECT_EQ(bad.validate(), "chat match_burst must be 1..1000, got 0");
}

}  // namespace
}  // namespace ricochet::server::chat_limiter_test
