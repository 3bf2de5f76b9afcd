// Three real ricochet-server processes on one PostgreSQL database (db.url, on this test process's
// cluster: postgres_cluster.h), started together and played over real sockets: the control
// channel's test client (tests/server/net/control_test_client.h) for accounts, sessions and
// limits, ricochet_bot for matches. One server's accounts, sessions, limits, ratings and
// leaderboard are every server's. Every wait is bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "control_test_client.h"
#include "postgres_cluster.h"
#include "ricochet/bot/bot.h"
#include "ricochet/db/store.h"
#include "run_until.h"
#include "server_process.h"

namespace ricochet::test {
namespace {

using namespace std::chrono_literals;
using server::test::ControlTestClient;
namespace asio = boost::asio;

/// As in bot_match_test.cpp: the bounded waits of a test add up to kMargin under ctest's limit.
constexpr std::chrono::seconds kCtestTimeout{RICOCHET_CTEST_TIMEOUT_S};
constexpr std::chrono::seconds kMargin{6};
/// From the forks to the three ports files (the servers start at once).
constexpr std::chrono::seconds kStartBudget{10};
/// The bots register, sign in, join and connect, and the results come back.
constexpr std::chrono::seconds kSignInBudget{15};
constexpr int kShutdownGraceS = 5;
constexpr std::chrono::seconds kExitBudget{kShutdownGraceS + 3};
/// Registrations per address and hour on every server: few, so the limit is reached cheaply.
constexpr int kRegistrationsPerAddress = 3;
/// The failed logins of one account from one address a minute (the default: PROTOCOL.md).
constexpr int kFailuresPerAccountAddress = 5;

/// The [matches] table: one free-for-all match of two players on the arena, seeded, no warm-up;
/// the first kill ends it (a decided match moves both ratings), the time limit if none comes.
std::string matches_toml(std::chrono::seconds time_limit) {
  return "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
         "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 1\nrecord = "
         "false\nmin_players = 2\nspawn_protection_s = 0\ntime_limit_s = " +
         std::to_string(time_limit.count()) + "\n";
}

/// Three servers on the database `url`, forked together; wait_listening() waits for all three.
class ThreeServers {
 public:
  ThreeServers(const std::string& url, std::chrono::seconds time_limit) {
    const std::string db = "[db]\nurl = \"" + url +
                           "\"\npassword_hashing = \"minimum\"\n"
                           "registrations_per_hour_per_address = " +
                           std::to_string(kRegistrationsPerAddress) + "\n";
    for (auto& server : servers_) {
      server = std::make_unique<ServerProcess>(matches_toml(time_limit), kShutdownGraceS, db);
    }
  }
  bool wait_listening() {
    for (auto& server : servers_) {
      if (!server->wait_listening(kStartBudget)) return false;
    }
    return true;
  }
  ServerProcess& operator[](std::size_t i) { return *servers_.at(i); }
  std::string logs() const {
    std::string text;
    for (std::size_t i = 0; i < servers_.size(); ++i) {
      text += "--- server " + std::string(1, static_cast<char>('A' + i)) + ":\n" +
              servers_[i]->log();
    }
    return text;
  }
  /// SIGTERM to all three, then each exit code (0 when all exited cleanly).
  bool stop() {
    for (auto& server : servers_) server->terminate();
    bool clean = true;
    for (auto& server : servers_) clean = server->wait_exit(kExitBudget) == 0 && clean;
    return clean;
  }

 private:
  std::array<std::unique_ptr<ServerProcess>, 3> servers_;
};

/// A control connection to `server` from the loopback address `source`.
std::unique_ptr<ControlTestClient> connect(ServerProcess& server,
                                           const std::string& source = "127.0.0.1") {
  auto client = std::make_unique<ControlTestClient>(server.control_port());
  EXPECT_TRUE(client->connect_from(source)) << "to port " << server.control_port();
  return client;
}

wire::ErrorCode error_of(const wire::ServerMessage& reply) {
  return reply.has_error() ? reply.error().code() : wire::ERROR_CODE_UNSPECIFIED;
}

TEST(MultiServer, AccountsSessionsAndLimitsOfOneServerHoldOnTheOthers) {
  static_assert(kStartBudget + kExitBudget + kMargin <= kCtestTimeout);
  ThreeServers servers(PostgresCluster::shared().create_database(), 60s);
  ASSERT_TRUE(servers.wait_listening()) << servers.logs();
  ServerProcess& a = servers[0];
  ServerProcess& b = servers[1];
  ServerProcess& c = servers[2];

  // An account registered on A signs in on B and on C, as the same account.
  const std::string password = "password-of-alice";
  const auto registered = connect(a)->request(ControlTestClient::register_account("alice", password));
  ASSERT_TRUE(registered.has_register_account()) << registered.DebugString();
  const std::uint64_t alice = registered.register_account().account_id();
  for (ServerProcess* server : {&b, &c}) {
    const auto reply = connect(*server)->request(ControlTestClient::login("alice", password));
    ASSERT_TRUE(reply.has_session()) << reply.DebugString();
    EXPECT_EQ(reply.session().account_id(), alice);
  }

  // A session token issued by A resumes on B and on C; revoked on B (logout), it resumes nowhere.
  const auto login = connect(a)->request(ControlTestClient::login("alice", password));
  ASSERT_TRUE(login.has_session()) << login.DebugString();
  const std::string token = login.session().session_token();
  ASSERT_EQ(token.size(), 64u);
  auto on_b = connect(b);
  auto on_c = connect(c);
  for (ControlTestClient* client : {on_b.get(), on_c.get()}) {
    const auto resumed = client->request(ControlTestClient::resume(token));
    ASSERT_TRUE(resumed.has_session()) << resumed.DebugString();
    EXPECT_EQ(resumed.session().account_id(), alice);
    EXPECT_EQ(resumed.session().username(), "alice");
    EXPECT_EQ(client->request(ControlTestClient::list_matches()).list_matches().matches_size(), 1);
  }
  EXPECT_TRUE(on_b->request(ControlTestClient::logout()).has_logout());
  EXPECT_EQ(error_of(connect(c)->request(ControlTestClient::resume(token))),
            wire::UNKNOWN_SESSION);

  // Wrong passwords for alice from 127.0.0.2 spread over A, B and C: the (account, address)
  // limit counts them all, and the next attempt on any server is refused, the right password too.
  const std::array<ServerProcess*, kFailuresPerAccountAddress> guessed_on = {&a, &b, &c, &a, &b};
  for (std::size_t i = 0; i < guessed_on.size(); ++i) {
    const auto reply = connect(*guessed_on[i], "127.0.0.2")
                           ->request(ControlTestClient::login("alice", "wrong-guess-" +
                                                                           std::to_string(i)));
    EXPECT_EQ(error_of(reply), wire::WRONG_CREDENTIALS) << "guess " << i << ": " << reply.DebugString();
  }
  for (ServerProcess* server : {&c, &a}) {
    const auto reply = connect(*server, "127.0.0.2")->request(ControlTestClient::login("alice", password));
    EXPECT_EQ(error_of(reply), wire::LOGIN_RATE_LIMITED) << reply.DebugString();
  }
  // The owner from another address is not limited by the guesser.
  const auto owner = connect(b, "127.0.0.3")->request(ControlTestClient::login("alice", password));
  EXPECT_TRUE(owner.has_session()) << owner.DebugString();

  // Registrations from 127.0.0.4, one on each server, reach the per-address limit: the next is
  // refused on every server; another address still registers.
  std::array<ServerProcess*, kRegistrationsPerAddress> registered_on = {&a, &b, &c};
  for (std::size_t i = 0; i < registered_on.size(); ++i) {
    const auto reply =
        connect(*registered_on[i], "127.0.0.4")
            ->request(ControlTestClient::register_account("newcomer" + std::to_string(i), password));
    EXPECT_TRUE(reply.has_register_account()) << "registration " << i << ": " << reply.DebugString();
  }
  for (ServerProcess* server : {&a, &b, &c}) {
    const auto reply = connect(*server, "127.0.0.4")
                           ->request(ControlTestClient::register_account("one-too-many", password));
    EXPECT_EQ(error_of(reply), wire::REGISTRATION_RATE_LIMITED) << reply.DebugString();
  }
  const auto elsewhere =
      connect(c, "127.0.0.5")->request(ControlTestClient::register_account("one-too-many", password));
  EXPECT_TRUE(elsewhere.has_register_account()) << elsewhere.DebugString();

  EXPECT_TRUE(servers.stop()) << servers.logs();
  if (HasFailure()) std::cout << servers.logs();
}

}  // namespace
}  // namespace ricochet::test
