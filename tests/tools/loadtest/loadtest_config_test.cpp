#include "ricochet/loadtest/loadtest_config.h"

#include <gtest/gtest.h>

#include <variant>

#include "ricochet/loadtest/error_kinds.h"
#include "ricochet/loadtest/fleet_plan.h"

namespace ricochet::loadtest::loadtest_config_test {
namespace {

TEST(LoadTestConfig, DefaultsAreValid) {
  EXPECT_EQ(LoadTestConfig{}.validate(), "");
}

TEST(LoadTestConfig, RefusesWhatIsOutOfRangeNamingIt) {
  LoadTestConfig config;
  config.servers[0].host = "example.com";
  EXPECT_NE(config.validate().find("numeric IPv4"), std::string::npos);
  config = {};
  config.servers.clear();
  EXPECT_EQ(config.validate(), "servers must be 1..64, got 0");
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

TEST(LoadTestConfig, FindMatchIsModeOrModeAndMapAsTheBotTakesIt) {
  LoadTestConfig config;
  config.find_match = "tdm";
  EXPECT_EQ(config.validate(), "");
  config.find_match = "ffa:arena";
  EXPECT_EQ(config.validate(), "");
  config.find_match = "TDM";
  EXPECT_NE(config.validate().find("find_match must be MODE or MODE:MAP"), std::string::npos)
      << config.validate();
  config.find_match = "tdm:";
  EXPECT_NE(config.validate().find("find_match's MAP"), std::string::npos) << config.validate();
}

TEST(LoadTestConfig, ServerListsTakeDefaultPortsAndNameWhatIsWrong) {
  const auto parsed = parse_servers("127.0.0.1,10.1.2.3:7000,127.0.0.2:7001:9001", 7777, 9100);
  ASSERT_TRUE(std::holds_alternative<std::vector<ServerEndpoint>>(parsed));
  const auto& servers = std::get<std::vector<ServerEndpoint>>(parsed);
  ASSERT_EQ(servers.size(), 3u);
  EXPECT_EQ(servers[0].label(), "127.0.0.1:7777");
  EXPECT_EQ(servers[0].admin_port, 9100);
  EXPECT_EQ(servers[1].host, "10.1.2.3");
  EXPECT_EQ(servers[1].control_port, 7000);
  EXPECT_EQ(servers[1].admin_port, 9100);
  EXPECT_EQ(servers[2].control_port, 7001);
  EXPECT_EQ(servers[2].admin_port, 9001);
  const auto error = [](const std::string& text) {
    const auto result = parse_servers(text, 7777, 9100);
    return std::holds_alternative<std::string>(result) ? std::get<std::string>(result) : "";
  };
  EXPECT_EQ(error("127.0.0.1,"), "server 2 (\"\"): expected a numeric IPv4 address");
  EXPECT_EQ(error("host:1"), "server 1 (\"host:1\"): expected a numeric IPv4 address");
  EXPECT_EQ(error("127.0.0.1:0"),
            "server 1 (\"127.0.0.1:0\"): expected a control port 1..65535 after the address");
  EXPECT_EQ(error("127.0.0.1:1:70000"),
            "server 1 (\"127.0.0.1:1:70000\"): expected an admin "
            "port 1..65535 after the control port");
  EXPECT_EQ(error("127.0.0.1:1:2:3"),
            "server 1 (\"127.0.0.1:1:2:3\"): expected an admin port "
            "1..65535 after the control port");
  EXPECT_EQ(error("127.0.0.1,127.0.0.1:7777"), "server 2 (\"127.0.0.1:7777\"): listed twice");
  std::string many = "127.0.0.1:1";
  for (int i = 2; i <= 65; ++i) many += ",127.0.0.1:" + std::to_string(i);
  EXPECT_EQ(error(many), "at most 64 servers, got more");
}

TEST(LoadTestConfig, BotsGoRoundRobinOverTheServers) {
  const auto plans = plan_fleets(5, 7, 3);  // bots 5..11 of the run
  ASSERT_EQ(plans.size(), 3u);
  EXPECT_EQ(plans[0].server, 0u);
  EXPECT_EQ(plans[0].bots, (std::vector<int>{6, 9}));
  EXPECT_EQ(plans[1].bots, (std::vector<int>{7, 10}));
  EXPECT_EQ(plans[2].bots, (std::vector<int>{5, 8, 11}));
  const auto one = plan_fleets(0, 1, 4);  // a server given no bot has no fleet
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].server, 0u);
  EXPECT_EQ(plan_fleets(0, 3, 1)[0].bots, (std::vector<int>{0, 1, 2}));
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
  // Placement's refusals, as the bot reports them (Bot::on_failure).
  EXPECT_EQ(error_kind("find_match tdm refused: UNKNOWN_MODE_OR_MAP: no server hosts tdm"),
            "unknown_mode_or_map");
  EXPECT_EQ(error_kind("find_match: SERVER_BUSY: the database is away"), "server_busy");
  EXPECT_EQ(error_kind("join_match with the ticket: NOT_SIGNED_IN: x"), "not_signed_in");
  EXPECT_EQ(error_kind("unusable assignment: game_port must be 1..65535, got 0"), "bad_assignment");
  // ... and those the bot answers by itself (Bot::report_refusal).
  EXPECT_EQ(error_kind("join_match with the ticket: MATCH_FULL: match 3 is full"), "match_full");
  EXPECT_EQ(error_kind("the ticket expired before it was presented"), "ticket_expired");
}

}  // namespace
}  // namespace ricochet::loadtest::loadtest_config_test
