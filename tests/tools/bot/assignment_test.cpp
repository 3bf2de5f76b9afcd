// Placement as the bot follows it (issue 31): --find-match's MODE[:MAP], and the server's
// Assignment read as untrusted input before the bot connects anywhere or pins anything.
#include "ricochet/bot/assignment.h"

#include <gtest/gtest.h>

#include <string>

#include "ricochet/bot/bot_config.h"

namespace ricochet::bot::assignment_test {
namespace {

constexpr proto::TimeUs kNow = 5 * proto::kMicrosPerSecond;

/// B's assignment as fleet_placement_test.cpp sees it: another server, a fresh ticket.
wire::Assignment elsewhere() {
  wire::Assignment assignment;
  assignment.set_connection("127.0.0.1:40123");
  assignment.set_game_port(40124);
  // Not std::string's operator+: GCC 12 at -O3 warns falsely of array bounds there.
  std::string fingerprint(62, 'a');
  fingerprint.append("0f");
  assignment.set_certificate_sha256(fingerprint);
  assignment.set_match_id(3);
  assignment.set_mode("tdm");
  assignment.set_ticket(std::string(32, '\x07'));
  assignment.set_ticket_expires_in_ms(30'000);
  return assignment;
}

std::string problem_of(const wire::Assignment& assignment) {
  const auto read = read_assignment(assignment, kNow);
  const auto* problem = std::get_if<std::string>(&read);
  return problem ? *problem : "";
}

TEST(MatchWanted, ModeAloneOrModeAndMapAsFindMatchTakesThem) {
  const auto tdm = std::get<MatchWanted>(parse_match_wanted("tdm"));
  EXPECT_EQ(tdm.mode, "tdm");
  EXPECT_EQ(tdm.map, "");
  const auto on_arena = std::get<MatchWanted>(parse_match_wanted("ffa:Arena-2.v1"));
  EXPECT_EQ(on_arena.mode, "ffa");
  EXPECT_EQ(on_arena.map, "Arena-2.v1");
  for (const char* bad : {"", ":arena", "TDM", "tdm:", "tdm:are na", "tdm:a:b", "t dm"}) {
    const auto parsed = parse_match_wanted(bad);
    ASSERT_TRUE(std::holds_alternative<std::string>(parsed)) << bad;
    EXPECT_NE(std::get<std::string>(parsed).find("find_match"), std::string::npos) << bad;
  }
  EXPECT_TRUE(std::holds_alternative<std::string>(parse_match_wanted(std::string(33, 'm'))));
  EXPECT_TRUE(std::holds_alternative<MatchWanted>(parse_match_wanted(std::string(32, 'm'))));
  EXPECT_TRUE(
      std::holds_alternative<std::string>(parse_match_wanted(std::string("tdm:").append(65, 'm'))));
}

TEST(MatchWanted, TheBotConfigRefusesABadOneAndOneWithAMatchId) {
  BotConfig config;
  config.trust_file = "unused";
  config.find_match = "tdm:arena";
  EXPECT_EQ(config.validate(), "");
  config.find_match = "Tdm";
  EXPECT_NE(config.validate().find("find_match must be MODE or MODE:MAP"), std::string::npos)
      << config.validate();
  config.find_match = "tdm";
  config.match_id = 2;
  EXPECT_NE(config.validate().find("find_match and match_id exclude each other"), std::string::npos)
      << config.validate();
}

TEST(Assignment, AnotherServersIsReadWithItsPinAndTheTicketsDeadlineOnTheBotsClock) {
  const auto read = read_assignment(elsewhere(), kNow);
  ASSERT_TRUE(std::holds_alternative<Assigned>(read)) << std::get<std::string>(read);
  const Assigned& assigned = std::get<Assigned>(read);
  EXPECT_FALSE(assigned.on_this_server);
  EXPECT_EQ(assigned.host.to_string(), "127.0.0.1");
  EXPECT_EQ(assigned.control_port, 40123);
  EXPECT_EQ(assigned.game_port, 40124);
  // ServerTrust's form: what the server logs and --fingerprint takes.
  std::string canonical;
  for (int i = 0; i < 31; ++i) canonical += "AA:";
  EXPECT_EQ(assigned.fingerprint, canonical + "0F");
  EXPECT_EQ(assigned.match_id, 3u);
  EXPECT_EQ(assigned.ticket, std::string(32, '\x07'));
  // Usable for the 30 s it was given, from when the reply came; not a microsecond after.
  EXPECT_TRUE(assigned.ticket_usable(kNow));
  EXPECT_TRUE(assigned.ticket_usable(kNow + 30 * proto::kMicrosPerSecond - 1));
  EXPECT_FALSE(assigned.ticket_usable(kNow + 30 * proto::kMicrosPerSecond));
  EXPECT_DOUBLE_EQ(assigned.ticket_left_s(kNow + 10 * proto::kMicrosPerSecond), 20.0);
  EXPECT_DOUBLE_EQ(assigned.ticket_left_s(kNow + 40 * proto::kMicrosPerSecond), 0.0);
}

TEST(Assignment, IPv6InBracketsIsReadAndOnThisServerNeedsOnlyTheTicket) {
  wire::Assignment v6 = elsewhere();
  v6.set_connection("[::1]:7777");
  const auto read = read_assignment(v6, kNow);
  ASSERT_TRUE(std::holds_alternative<Assigned>(read)) << std::get<std::string>(read);
  EXPECT_EQ(std::get<Assigned>(read).host.to_string(), "::1");
  EXPECT_EQ(std::get<Assigned>(read).control_port, 7777);

  wire::Assignment here;
  here.set_ticket(std::string(32, 'x'));
  here.set_ticket_expires_in_ms(1000);
  here.set_on_this_server(true);
  const auto local = read_assignment(here, kNow);
  ASSERT_TRUE(std::holds_alternative<Assigned>(local)) << std::get<std::string>(local);
  EXPECT_TRUE(std::get<Assigned>(local).on_this_server);
  EXPECT_FALSE(std::get<Assigned>(local).ticket_usable(kNow + proto::kMicrosPerSecond));
}

TEST(Assignment, EveryBadFieldRefusesTheWholeReplyWithWhatCame) {
  wire::Assignment assignment = elsewhere();
  assignment.set_ticket("short");
  EXPECT_EQ(problem_of(assignment), "a ticket of 5 bytes, expected 32");
  // The ticket is checked on this server too.
  assignment.set_on_this_server(true);
  EXPECT_EQ(problem_of(assignment), "a ticket of 5 bytes, expected 32");

  const std::pair<const char*, const char*> connections[] = {
      {"127.0.0.1", "connection must be host:port"},
      {"game.example.com:7777", "numeric IP address"},
      {"::1:7777", "[address]:port"},
      {"127.0.0.1:0", "port must be 1..65535"},
      {"127.0.0.1:65536", "port must be 1..65535"},
      {"127.0.0.1:77x", "port must be 1..65535"},
      {"127.0.0.1:", "port must be 1..65535"},
  };
  for (const auto& [connection, expected] : connections) {
    assignment = elsewhere();
    assignment.set_connection(connection);
    const std::string problem = problem_of(assignment);
    EXPECT_NE(problem.find(expected), std::string::npos) << connection << ": " << problem;
    EXPECT_NE(problem.find(connection), std::string::npos) << problem;
  }
  assignment = elsewhere();
  assignment.set_game_port(0);
  EXPECT_EQ(problem_of(assignment), "game_port must be 1..65535, got 0");
  assignment.set_game_port(70000);
  EXPECT_EQ(problem_of(assignment), "game_port must be 1..65535, got 70000");
  std::string colon_form = "AA";
  for (int i = 0; i < 31; ++i) colon_form += ":AA";
  for (const std::string& fingerprint : {std::string(), std::string(63, 'a'), std::string(64, 'g'),
                                         // The log's form, not the directory's (PROTOCOL.md).
                                         colon_form}) {
    assignment = elsewhere();
    assignment.set_certificate_sha256(fingerprint);
    EXPECT_NE(problem_of(assignment).find("certificate_sha256 must be 64 hex digits"),
              std::string::npos)
        << fingerprint;
  }
}

}  // namespace
}  // namespace ricochet::bot::assignment_test
