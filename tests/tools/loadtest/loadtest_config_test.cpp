#include "ricochet/loadtest/loadtest_config.h"

#include <gtest/gtest.h>

#include "ricochet/loadtest/error_kinds.h"

namespace ricochet::loadtest::loadtest_config_test {
namespace {

TEST(LoadTestConfig, DefaultsAreValid) {
  EXPECT_EQ(LoadTestConfig{}.validate(), "");
}

TEST(LoadTestConfig, RefusesWhatIsOutOfRangeNamingIt) {
  LoadTestConfig config;
  config.server = "192.168.1.4";
  EXPECT_NE(config.validate().find("loopback"), std::string::npos);
  config = {};
  config.sweep = {100, 20000};
  EXPECT_EQ(config.validate(), "bots must be 1..10000, got 20000");
  config = {};
  config.bots_per_address = 17;
  EXPECT_NE(config.validate().find("bots_per_address must be 1..16"), std::string::npos);
  config = {};
  config.ramp_per_s = 0;
  EXPECT_EQ(config.validate(), "ramp_per_s must be 0.1..1000 bots per second, got 0");
  config = {};
  config.name = "has space";
  EXPECT_NE(config.validate().find("name must be"), std::string::npos);
}

TEST(LoadTestConfig, DurationsAndBotCounts) {
  EXPECT_EQ(parse_duration_s("60"), 60);
  EXPECT_EQ(parse_duration_s("60s"), 60);
  EXPECT_EQ(parse_duration_s("1.5m"), 90);
  EXPECT_EQ(parse_duration_s("250ms"), 0.25);
  EXPECT_FALSE(parse_duration_s("-1s"));
  EXPECT_FALSE(parse_duration_s("1h"));
  EXPECT_FALSE(parse_duration_s("s"));
  EXPECT_EQ(parse_bot_counts("100,200,400"), (std::vector<int>{100, 200, 400}));
  EXPECT_FALSE(parse_bot_counts(""));
  EXPECT_FALSE(parse_bot_counts("100,"));
  EXPECT_FALSE(parse_bot_counts("200,100"));
  EXPECT_FALSE(parse_bot_counts("0"));
  EXPECT_FALSE(parse_bot_counts("1;2"));
}

TEST(LoadTestConfig, SourceAddressesAreLoopbackAndDistinct) {
  const auto addresses = source_addresses(300);
  ASSERT_EQ(addresses.size(), 300u);
  EXPECT_EQ(addresses[0], "127.0.1.1");
  EXPECT_EQ(addresses[253], "127.0.1.254");
  EXPECT_EQ(addresses[254], "127.0.2.1");
  for (const auto& address : addresses) EXPECT_TRUE(is_loopback_v4(address)) << address;
  EXPECT_FALSE(is_loopback_v4("128.0.0.1"));
  EXPECT_FALSE(is_loopback_v4("::1"));
}

TEST(ErrorKinds, NameTheServersCodeOrWhatFailed) {
  EXPECT_EQ(error_kind("login: LOGIN_RATE_LIMITED: too many logins"), "login_rate_limited");
  EXPECT_EQ(error_kind("join_match: MATCH_FULL: match 3 is full"), "match_full");
  EXPECT_EQ(error_kind("timed out signing in"), "timeout_sign_in");
  EXPECT_EQ(error_kind("cannot connect: Connection refused"), "connect_failed");
  EXPECT_EQ(error_kind("game channel ended: timed_out"), "game_lost_timed_out");
  EXPECT_EQ(error_kind("gave up after 5 failed attempts in a row; the last: x"), "gave_up");
  EXPECT_EQ(error_kind("control channel lost: the server closed the connection"), "control_lost");
  EXPECT_EQ(error_kind("TLS handshake failed (a server at its connection cap closes before TLS)"),
            "tls_failed");
  EXPECT_EQ(error_kind("something else"), "other");
}

}  // namespace
}  // namespace ricochet::loadtest::loadtest_config_test
