// Seats and matches cannot be hoarded (issue 29), over real loopback sockets against the Server
// as ricochet-server runs it. Attackers and victims come from their own loopback addresses
// (127.0.0.2, 127.0.0.3 ...), which is what the per-address limits count. Each test asserts
// what the victim sees: it joins within 2 s and plays, while the attacker is refused and counted
// in /metrics.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "control_test_client.h"
#include "game_test_client.h"
#include "server.h"
#include "temp_dir.h"

namespace ricochet::test::seat_limits_test {
namespace {

using namespace std::chrono_literals;
using server::test::ControlTestClient;

class SeatLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    server::ServerConfig config;
    config.server.data_dir = (dir_.path() / "data").string();
    config.server.threads = 2;
    config.server.shutdown_grace_s = 5;
    config.db.password_hashing = server::PasswordHashing::Minimum;  // many accounts, quickly
    config.control.bind = "127.0.0.1";
    config.control.port = 0;
    config.game.bind = "127.0.0.1";
    config.game.port = 0;
    config.admin.port = 0;
    config.matches.count = 3;
    config.matches.max_players = 8;
    config.matches.min_players = 1;
    config.matches.warmup_s = 0;
    config.matches.maps = {RICOCHET_SOURCE_DIR "/server/maps/arena.toml"};
    server_ = std::make_unique<server::Server>(config);
    server_->start();
  }
  void TearDown() override { server_.reset(); }

  /// A signed-in control connection from `source`.
  std::unique_ptr<ControlTestClient> signed_in(const std::string& name, const std::string& source,
                                               bool fresh = true) {
    auto client = std::make_unique<ControlTestClient>(server_->control_port());
    EXPECT_TRUE(client->connect_from(source)) << name << " from " << source;
    client->sign_in(name, fresh);
    return client;
  }
  std::vector<std::uint32_t> match_ids(ControlTestClient& client) {
    std::vector<std::uint32_t> ids;
    const auto reply = client.request(ControlTestClient::list_matches());
    for (const auto& match : reply.list_matches().matches()) ids.push_back(match.match_id());
    return ids;
  }
  /// The value of one /metrics line starting with `series`, or -1.
  double metric(const std::string& series) {
    const std::string text = server_->metrics().render();
    const auto at = text.find("\n" + series + " ");
    if (at == std::string::npos) return -1;
    return std::stod(text.substr(at + series.size() + 2));
  }

  TempDir dir_{"ricochet-seats"};
  std::unique_ptr<server::Server> server_;
};

TEST_F(SeatLimits, ReservationsFromOneAddressCannotKeepAVictimOut) {
  auto probe = signed_in("probe", "127.0.0.9");
  const std::uint32_t match = match_ids(*probe).front();
  // The attacker: 8 accounts on 127.0.0.2 join the 8-seat match and never open the game channel.
  std::vector<std::unique_ptr<ControlTestClient>> attacker;
  int seated = 0;
  for (int i = 0; i < 8; ++i) {
    attacker.push_back(signed_in("hoarder" + std::to_string(i), "127.0.0.2"));
    seated += attacker.back()->request(ControlTestClient::join(match)).has_join_match() ? 1 : 0;
  }
  EXPECT_EQ(seated, 4);  // half the match's seats may wait for their players at once

  // The victim, from another address, asks as a client does after MATCH_FULL (again a moment
  // later): a reservation left unused for a second gives way to it.
  auto victim = signed_in("victim", "127.0.0.3");
  const auto asked = std::chrono::steady_clock::now();
  wire::ServerMessage reply = victim->request(ControlTestClient::join(match));
  while (!reply.has_join_match() && std::chrono::steady_clock::now() - asked < 3s) {
    EXPECT_EQ(reply.error().code(), wire::MATCH_FULL) << reply.DebugString();
    std::this_thread::sleep_for(100ms);
    reply = victim->request(ControlTestClient::join(match));
  }
  ASSERT_TRUE(reply.has_join_match()) << reply.DebugString();
  EXPECT_LT(std::chrono::steady_clock::now() - asked, 2s);
  GameTestClient game(reply.join_match(), server_->game_port());
  EXPECT_TRUE(game.pump_until(proto::ConnectionState::Connected, 2s));
  EXPECT_GE(metric("ricochet_match_limit_refused_total{reason=\"reserved_seats\"}"), 5);
}

TEST_F(SeatLimits, OneAddressHoldsAtMostEightSeatsAcrossTheMatches) {
  auto probe = signed_in("probe", "127.0.0.9");
  const std::vector<std::uint32_t> matches = match_ids(*probe);
  ASSERT_EQ(matches.size(), 3u);
  // 4 reservations in each of the first two matches, then a ninth seat anywhere.
  std::vector<std::unique_ptr<ControlTestClient>> attacker;
  for (int i = 0; i < 8; ++i) {
    attacker.push_back(signed_in("hoarder" + std::to_string(i), "127.0.0.2"));
    const auto reply = attacker.back()->request(ControlTestClient::join(matches[i / 4]));
    EXPECT_TRUE(reply.has_join_match()) << i << ": " << reply.DebugString();
  }
  attacker.push_back(signed_in("hoarder8", "127.0.0.2"));
  const auto ninth = attacker.back()->request(ControlTestClient::join(matches[2]));
  ASSERT_TRUE(ninth.has_error());
  EXPECT_EQ(ninth.error().code(), wire::ADDRESS_SEAT_LIMIT) << ninth.DebugString();
  EXPECT_EQ(metric("ricochet_match_limit_refused_total{reason=\"address_seats\"}"), 1);

  auto victim = signed_in("victim", "127.0.0.3");
  EXPECT_TRUE(victim->request(ControlTestClient::join(matches[2])).has_join_match());
}

TEST_F(SeatLimits, ASecondSessionOfTheAccountTakesItsSeatOver) {
  auto first = signed_in("twice", "127.0.0.2");
  const std::uint32_t match = match_ids(*first).front();
  const wire::ServerMessage joined = first->request(ControlTestClient::join(match));
  ASSERT_TRUE(joined.has_join_match());
  GameTestClient first_game(joined.join_match(), server_->game_port());
  ASSERT_TRUE(first_game.pump_until(proto::ConnectionState::Connected, 2s));

  // The same account from a second control connection: it is played from there now.
  auto second = signed_in("twice", "127.0.0.3", false);
  const wire::ServerMessage rejoined = second->request(ControlTestClient::join(match));
  ASSERT_TRUE(rejoined.has_join_match()) << rejoined.DebugString();
  EXPECT_TRUE(first_game.pump_until(proto::ConnectionState::Disconnected, 2s));
  GameTestClient second_game(rejoined.join_match(), server_->game_port());
  EXPECT_TRUE(second_game.pump_until(proto::ConnectionState::Connected, 2s));

  // The first connection no longer plays it: its leave is refused, the seat stays.
  const wire::ServerMessage stale = first->request(ControlTestClient::leave());
  ASSERT_TRUE(stale.has_error());
  EXPECT_EQ(stale.error().code(), wire::NOT_IN_MATCH);
  const wire::ServerMessage listed = second->request(ControlTestClient::list_matches());
  for (const auto& info : listed.list_matches().matches()) {
    if (info.match_id() == match) {
      EXPECT_EQ(info.players(), 1u);
    }
  }
  EXPECT_TRUE(second->request(ControlTestClient::leave()).has_leave_match());
}

TEST_F(SeatLimits, AnAccountHasOneCreatedMatchOpen) {
  auto creator = signed_in("creator", "127.0.0.2");
  wire::ClientMessage create;
  create.mutable_create_match()->set_name("mine");
  create.mutable_create_match()->set_max_players(4);
  const auto made = creator->request(create);
  ASSERT_TRUE(made.has_create_match()) << made.DebugString();
  const auto again = creator->request(create);
  ASSERT_TRUE(again.has_error());
  EXPECT_EQ(again.error().code(), wire::TOO_MANY_MATCHES) << again.DebugString();
  EXPECT_EQ(metric("ricochet_match_limit_refused_total{reason=\"account_matches\"}"), 1);
  // Another account still creates one.
  auto other = signed_in("other", "127.0.0.3");
  EXPECT_TRUE(other->request(create).has_create_match());
}

}  // namespace
}  // namespace ricochet::test::seat_limits_test
