// Placement across a fleet (PROTOCOL.md, Placement): two real ricochet-server processes on one
// PostgreSQL database, each listing both (and where their admin ports are) on GET /fleet, a
// client signed in on one sent to the other by find_match, joining there with its ticket.

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/json.hpp>
#include <cctype>
#include <chrono>
#include <optional>
#include <string>
#include <thread>

#include "admin_get.h"
#include "control_test_client.h"
#include "postgres_cluster.h"
#include "server_process.h"

namespace ricochet::server::test::fleet_placement_test {
namespace {

using ricochet::test::PostgresCluster;
using ricochet::test::ServerProcess;

/// One match of `mode` on the test map, nobody needed to start it.
std::string matches_of(const std::string& mode) {
  return "count = 1\nmax_players = 8\nmode = \"" + mode +
         "\"\nmaps = [\"" RICOCHET_SOURCE_DIR
         "/server/maps/arena.toml\"]\nseed = 7\nwarmup_s = 0\nrecord = false\n";
}

std::string fleet_toml(const std::string& url) {
  return "[db]\nurl = \"" + url +
         "\"\npassword_hashing = \"minimum\"\n[placement]\nadvertise_host = \"127.0.0.1\"\n"
         "heartbeat_s = 1\nserver_ttl_s = 5\n";
}

/// The fingerprint as the directory keeps it: 64 lowercase hex digits, no colons.
std::string directory_form(std::string fingerprint) {
  std::erase(fingerprint, ':');
  std::transform(fingerprint.begin(), fingerprint.end(), fingerprint.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return fingerprint;
}

/// Waits until the server logs that its directory row was written.
bool listed(const ServerProcess& server, std::chrono::milliseconds limit = 5s) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (server.log().find("is in the fleet directory") == std::string::npos) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

wire::ClientMessage find_match(const std::string& mode) {
  wire::ClientMessage m;
  m.mutable_find_match()->set_mode(mode);
  return m;
}

wire::ClientMessage join_with(const std::string& ticket) {
  wire::ClientMessage m;
  m.mutable_join_match()->set_ticket(ticket);
  return m;
}

TEST(FleetPlacement, FindMatchOnOneServerSeatsThePlayerOnTheOtherWithItsTicketOnce) {
  const std::string url = PostgresCluster::shared().create_database();
  // A hosts only ffa, B only tdm: a tdm player on A can only be placed on B.
  ServerProcess a(matches_of("ffa"), 5, fleet_toml(url));
  ServerProcess b(matches_of("tdm"), 5, fleet_toml(url));
  ASSERT_TRUE(a.wait_listening()) << a.log();
  ASSERT_TRUE(b.wait_listening()) << b.log();
  ASSERT_TRUE(listed(a)) << a.log();
  ASSERT_TRUE(listed(b)) << b.log();

  // Either server lists both on /fleet, itself as self, with the admin port each advertises
  // (bound to loopback, advertised as 127.0.0.1: reachable there) and its one match.
  const std::string listing = ricochet::test::admin_response(b.admin_port(), "/fleet");
  ASSERT_EQ(ricochet::test::status_line(listing), "HTTP/1.1 200 OK") << listing;
  const boost::json::value fleet = boost::json::parse(ricochet::test::body_of(listing));
  const boost::json::array& rows = fleet.at("servers").as_array();
  ASSERT_EQ(rows.size(), 2u) << listing;
  int selves = 0;
  for (const boost::json::value& row : rows) {
    const bool is_b = row.at("control_port").as_int64() == b.control_port();
    const ServerProcess& server = is_b ? b : a;
    EXPECT_EQ(row.at("self").as_bool(), is_b) << listing;
    selves += row.at("self").as_bool() ? 1 : 0;
    EXPECT_EQ(row.at("host").as_string(), "127.0.0.1");
    EXPECT_EQ(row.at("game_port").as_int64(), server.game_port()) << listing;
    EXPECT_EQ(row.at("admin_port").as_int64(), server.admin_port()) << listing;
    EXPECT_EQ(row.at("certificate_sha256").as_string(), directory_form(server.fingerprint()));
    EXPECT_LT(row.at("heartbeat_age_ms").as_int64(), 5'000) << listing;  // the TTL
    const boost::json::array& hosted = row.at("matches").as_array();
    ASSERT_EQ(hosted.size(), 1u) << listing;
    EXPECT_EQ(hosted[0].at("mode").as_string(), is_b ? "tdm" : "ffa") << listing;
  }
  EXPECT_EQ(selves, 1) << listing;

  ControlTestClient on_a(a.control_port());
  ASSERT_TRUE(on_a.connect());
  const wire::SessionReply session = on_a.sign_in("placed");
  const wire::ServerMessage found = on_a.request(find_match("tdm"));
  ASSERT_TRUE(found.has_find_match()) << found.DebugString();
  const wire::Assignment& assignment = found.find_match().assignment();
  EXPECT_EQ(assignment.connection(), "127.0.0.1:" + std::to_string(b.control_port()));
  EXPECT_EQ(assignment.game_port(), b.game_port());
  EXPECT_EQ(assignment.certificate_sha256(), directory_form(b.fingerprint()));
  EXPECT_EQ(assignment.mode(), "tdm");
  EXPECT_EQ(assignment.match_id(), 1u);  // B's only match, open with a seat
  EXPECT_FALSE(assignment.on_this_server());
  EXPECT_EQ(assignment.ticket().size(), 32u);
  EXPECT_GT(assignment.ticket_expires_in_ms(), 0u);
  // Nothing of ffa's kind elsewhere: A's own match is the only one.
  const wire::ServerMessage own = on_a.request(find_match("ffa"));
  ASSERT_TRUE(own.has_find_match()) << own.DebugString();
  EXPECT_TRUE(own.find_match().assignment().on_this_server());
  const wire::ServerMessage nowhere = on_a.request(find_match("ctf"));
  EXPECT_EQ(nowhere.error().code(), wire::UNKNOWN_MODE_OR_MAP) << nowhere.DebugString();

  // The tdm ticket was dropped by the ffa find_match (one open ticket per account): find again.
  const wire::ServerMessage again = on_a.request(find_match("tdm"));
  ASSERT_TRUE(again.has_find_match()) << again.DebugString();
  const std::string ticket = again.find_match().assignment().ticket();

  ControlTestClient on_b(b.control_port());
  ASSERT_TRUE(on_b.connect());
  EXPECT_EQ(on_b.peer_fingerprint(), b.fingerprint());
  wire::ClientMessage resume;
  resume.mutable_resume()->set_session_token(session.session_token());
  const wire::ServerMessage resumed = on_b.request(resume);
  ASSERT_TRUE(resumed.has_session()) << resumed.DebugString();
  // The first ticket went with the find_match after it.
  EXPECT_EQ(on_b.request(join_with(assignment.ticket())).error().code(), wire::UNKNOWN_TICKET);
  const wire::ServerMessage joined = on_b.request(join_with(ticket));
  ASSERT_TRUE(joined.has_join_match()) << joined.DebugString();
  EXPECT_EQ(joined.join_match().match_id(), assignment.match_id());
  EXPECT_EQ(joined.join_match().udp_port(), b.game_port());
  EXPECT_EQ(on_b.state(), proto::ControlState::InMatch);
  wire::ClientMessage list;
  list.mutable_list_matches();
  const wire::ServerMessage matches = on_b.request(list);
  ASSERT_EQ(matches.list_matches().matches_size(), 1) << matches.DebugString();
  EXPECT_EQ(matches.list_matches().matches(0).players(), 1u);

  // Used once: the same ticket again is unknown, on B and on A.
  EXPECT_EQ(on_b.request(join_with(ticket)).error().code(), wire::UNKNOWN_TICKET);
  EXPECT_EQ(on_a.request(join_with(ticket)).error().code(), wire::UNKNOWN_TICKET);
  EXPECT_EQ(on_a.request(join_with("short")).error().code(), wire::UNKNOWN_TICKET);

  // B drains on SIGTERM and leaves the directory first: at once, nobody hosts tdm any more
  // (its row would otherwise stay live for server_ttl_s).
  b.terminate();
  ASSERT_EQ(b.wait_exit(8s), std::optional<int>(0)) << b.log();
  EXPECT_NE(b.log().find("left the fleet directory"), std::string::npos) << b.log();
  const wire::ServerMessage gone = on_a.request(find_match("tdm"));
  EXPECT_EQ(gone.error().code(), wire::UNKNOWN_MODE_OR_MAP) << gone.DebugString();
}

}  // namespace
}  // namespace ricochet::server::test::fleet_placement_test
