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
#include <thread>
#include <vector>

#include "control_test_client.h"
#include "ctest_budget.h"
#include "postgres_cluster.h"
#include "ricochet/bot/bot.h"
#include "ricochet/bot/control_client.h"
#include "ricochet/bot/server_trust.h"
#include "ricochet/db/accounts.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"
#include "run_until.h"
#include "server_process.h"

namespace ricochet::test::multi_server_test {
namespace {

using namespace std::chrono_literals;
using server::test::ControlTestClient;
namespace asio = boost::asio;

/// From the forks to the three ports files (the servers start at once).
constexpr std::chrono::seconds kStartBudget{10};
/// The bots register (at the minimum password cost), sign in, join and connect, and the
/// results come back.
constexpr std::chrono::seconds kSignInBudget{10};
constexpr int kShutdownGraceS = 5;
constexpr std::chrono::seconds kExitBudget{kShutdownGraceS + 3};
/// Registrations per address and hour on every server in the test of the limits: few, so the
/// limit is reached cheaply.
constexpr int kRegistrationsPerAddress = 3;
/// The failed logins of one account from one address a minute (the default: PROTOCOL.md).
constexpr int kFailuresPerAccountAddress = 5;

/// The [matches] table: one free-for-all match of two players on the arena, seeded, no warm-up,
/// no frag limit: the time limit ends it, so matches that start together end together.
std::string matches_toml(std::chrono::seconds time_limit) {
  return "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
         "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\nrecord = "
         "false\nmin_players = 2\ntime_limit_s = " +
         std::to_string(time_limit.count()) + "\n";
}

/// Three servers on the database `url`, forked together; wait_listening() waits for all three.
class ThreeServers {
 public:
  ThreeServers(const std::string& url, std::chrono::seconds time_limit,
               int registrations_per_address = 10) {
    const std::string db = "[db]\nurl = \"" + url +
                           "\"\npassword_hashing = \"minimum\"\n"
                           "registrations_per_hour_per_address = " +
                           std::to_string(registrations_per_address) + "\n";
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
      text +=
          "--- server " + std::string(1, static_cast<char>('A' + i)) + ":\n" + servers_[i]->log();
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

/// Two bots playing one match each: `names` on `server`, registering if new, at skill 1.
class Pair {
 public:
  Pair(asio::io_context& io, asio::ssl::context& tls, const ServerProcess& server,
       const std::array<std::string, 2>& names)
      : trust_(bot::ServerTrust::pinned(server.fingerprint())) {
    for (std::size_t i = 0; i < names.size(); ++i) {
      bot::BotConfig config;
      config.host = "127.0.0.1";
      config.control_port = server.control_port();
      config.fingerprint = server.fingerprint();
      config.name = names[i];
      config.password = "password-of-" + names[i];
      config.skill = 1;
      config.seed = i + 1;
      config.matches = 1;
      bots_[i] = std::make_unique<bot::Bot>(io, tls, trust_, config);
    }
  }
  void start() {
    for (auto& each : bots_) each->start();
  }
  bool done() const {
    return std::all_of(bots_.begin(), bots_.end(),
                       [](const auto& each) { return each->state() == bot::BotState::Done; });
  }
  /// The match's results as the first bot got them (empty when it got none).
  wire::MatchResults results() const {
    const auto& record = bots_[0]->record();
    return record.results.empty() ? wire::MatchResults{} : record.results[0];
  }
  /// What went wrong for each bot (an error, not one match's results); empty when nothing did.
  std::string errors() const {
    std::string text;
    for (const auto& each : bots_) {
      if (!each->record().error.empty())
        text += each->config().name + ": " + each->record().error + "\n";
      if (each->record().results.size() != 1)
        text += each->config().name + ": " + std::to_string(each->record().results.size()) +
                " results\n";
    }
    return text;
  }

 private:
  bot::ServerTrust trust_;
  std::array<std::unique_ptr<bot::Bot>, 2> bots_;
};

/// The result of the account named `name` in `results`; throws when it has none.
const wire::PlayerMatchResult& result_of(const wire::MatchResults& results,
                                         const std::string& name) {
  for (const wire::PlayerMatchResult& player : results.players()) {
    if (player.username() == name) return player;
  }
  throw std::runtime_error("no result of " + name + " in " + results.DebugString());
}

wire::ErrorCode error_of(const wire::ServerMessage& reply) {
  return reply.has_error() ? reply.error().code() : wire::ERROR_CODE_UNSPECIFIED;
}

TEST(MultiServer, AccountsSessionsAndLimitsOfOneServerHoldOnTheOthers) {
  static_assert(fits_ctest(kStartBudget + kExitBudget));
  ThreeServers servers(PostgresCluster::shared().create_database(), 60s, kRegistrationsPerAddress);
  ASSERT_TRUE(servers.wait_listening()) << servers.logs();
  ServerProcess& a = servers[0];
  ServerProcess& b = servers[1];
  ServerProcess& c = servers[2];

  // An account registered on A signs in on B and on C, as the same account.
  const std::string password = "password-of-alice";
  const auto registered =
      connect(a)->request(ControlTestClient::register_account("alice", password));
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
  EXPECT_EQ(error_of(connect(c)->request(ControlTestClient::resume(token))), wire::UNKNOWN_SESSION);

  // Wrong passwords for alice from 127.0.0.2 spread over A, B and C: the (account, address)
  // limit counts them all, and the next attempt on any server is refused, the right password too.
  const std::array<ServerProcess*, kFailuresPerAccountAddress> guessed_on = {&a, &b, &c, &a, &b};
  for (std::size_t i = 0; i < guessed_on.size(); ++i) {
    const auto reply =
        connect(*guessed_on[i], "127.0.0.2")
            ->request(ControlTestClient::login("alice", "wrong-guess-" + std::to_string(i)));
    EXPECT_EQ(error_of(reply), wire::WRONG_CREDENTIALS)
        << "guess " << i << ": " << reply.DebugString();
  }
  for (ServerProcess* server : {&c, &a}) {
    const auto reply =
        connect(*server, "127.0.0.2")->request(ControlTestClient::login("alice", password));
    EXPECT_EQ(error_of(reply), wire::LOGIN_RATE_LIMITED) << reply.DebugString();
  }
  // The owner from another address is not limited by the guesser.
  const auto owner = connect(b, "127.0.0.3")->request(ControlTestClient::login("alice", password));
  EXPECT_TRUE(owner.has_session()) << owner.DebugString();

  // Registrations from 127.0.0.4, one on each server, reach the per-address limit: the next is
  // refused on every server; another address still registers.
  std::array<ServerProcess*, kRegistrationsPerAddress> registered_on = {&a, &b, &c};
  for (std::size_t i = 0; i < registered_on.size(); ++i) {
    const auto reply = connect(*registered_on[i], "127.0.0.4")
                           ->request(ControlTestClient::register_account(
                               "newcomer" + std::to_string(i), password));
    EXPECT_TRUE(reply.has_register_account())
        << "registration " << i << ": " << reply.DebugString();
  }
  for (ServerProcess* server : {&a, &b, &c}) {
    const auto reply = connect(*server, "127.0.0.4")
                           ->request(ControlTestClient::register_account("one-too-many", password));
    EXPECT_EQ(error_of(reply), wire::REGISTRATION_RATE_LIMITED) << reply.DebugString();
  }
  const auto elsewhere =
      connect(c, "127.0.0.5")
          ->request(ControlTestClient::register_account("one-too-many", password));
  EXPECT_TRUE(elsewhere.has_register_account()) << elsewhere.DebugString();

  // One name registered on A and on B at the same moment (a client each, on threads of their
  // own) is one account: one registration succeeds, the other is DUPLICATE_USERNAME.
  for (int round = 0; round < 3; ++round) {
    const std::string name = "racer" + std::to_string(round);
    auto from_a = connect(a, "127.0.0.6");
    auto from_b = connect(b, "127.0.0.7");
    std::array<wire::ServerMessage, 2> replies;
    std::thread on_a(
        [&] { replies[0] = from_a->request(ControlTestClient::register_account(name, password)); });
    replies[1] = from_b->request(ControlTestClient::register_account(name, password));
    on_a.join();
    int accounts = 0;
    int duplicates = 0;
    for (const wire::ServerMessage& reply : replies) {
      accounts += reply.has_register_account();
      duplicates += error_of(reply) == wire::DUPLICATE_USERNAME;
    }
    EXPECT_TRUE(accounts == 1 && duplicates == 1)
        << replies[0].DebugString() << replies[1].DebugString();
  }

  EXPECT_TRUE(servers.stop()) << servers.logs();
  if (HasFailure()) std::cout << servers.logs();
}

TEST(MultiServer, MatchesOnTwoServersAtOnceMoveTheSameRatingsAndAThirdSeesBoth) {
  // The same two accounts play a match on A and one on B at the same time (both end on the time
  // limit, so their results are written together), then one on C. Each server records a match
  // in one transaction that reads the ratings it moves, so one of A's and B's records starts
  // from the other's ratings (none is lost), and C's starts from both.
  constexpr std::chrono::seconds kTimeLimit{2};
  static_assert(fits_ctest(kStartBudget + 2 * (kTimeLimit + kSignInBudget) + kExitBudget));
  const std::string url = PostgresCluster::shared().create_database();
  const std::array<std::string, 2> names = {"xavier", "yvonne"};
  // The accounts, and a match the first won, written before the servers start: with unequal
  // ratings every outcome moves both (a draw between equal ratings would not, and would hide a
  // lost update).
  std::array<db::AccountId, 2> ids{};
  std::array<double, 2> seeded{};  ///< their ratings after it
  {
    auto store = db::open_store({.url_or_path = url});
    ASSERT_TRUE(store.ok()) << store.error().message;
    db::AccountsOptions minimum;
    minimum.cost = db::PasswordCost::Minimum;
    db::Accounts accounts(*store.value(), minimum);
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto id = accounts.register_account(names[i], "password-of-" + names[i], "", 1000);
      ASSERT_TRUE(id.ok()) << id.error().message;
      ids[i] = id.value();
    }
    db::MatchRecord won;
    won.uuid = db::new_match_uuid();
    won.map = "arena";
    won.started_ms = 1000;
    won.ended_ms = 61'000;
    won.players = {{.account = ids[0], .kills = 1, .score = 1, .seconds_played = 60},
                   {.account = ids[1], .deaths = 1, .seconds_played = 60}};
    const auto recorded = db::Matches(*store.value()).record_match(won);
    ASSERT_TRUE(recorded.ok()) << recorded.error().message;
    for (std::size_t i = 0; i < names.size(); ++i)
      seeded[i] = recorded.value().outcomes[i].rating_after;
    ASSERT_NE(seeded[0], seeded[1]);
  }
  ThreeServers servers(url, kTimeLimit);
  ASSERT_TRUE(servers.wait_listening()) << servers.logs();
  asio::io_context io;
  auto tls = bot::make_control_tls_context();
  Pair on_a(io, tls, servers[0], names);
  Pair on_b(io, tls, servers[1], names);
  on_a.start();
  on_b.start();
  ASSERT_TRUE(run_until(
      io, [&] { return on_a.done() && on_b.done(); }, kTimeLimit + kSignInBudget))
      << on_a.errors() << on_b.errors() << servers.logs();
  ASSERT_EQ(on_a.errors() + on_b.errors(), "") << servers.logs();
  Pair on_c(io, tls, servers[2], names);
  on_c.start();
  ASSERT_TRUE(run_until(
      io, [&] { return on_c.done(); }, kTimeLimit + kSignInBudget))
      << on_c.errors() << servers.logs();
  ASSERT_EQ(on_c.errors(), "") << servers.logs();

  const wire::MatchResults a = on_a.results();
  const wire::MatchResults b = on_b.results();
  const wire::MatchResults c = on_c.results();
  for (const wire::MatchResults* results : {&a, &b, &c}) {
    ASSERT_EQ(results->players_size(), 2) << results->DebugString();
    EXPECT_FALSE(results->aborted()) << results->DebugString();
  }
  // One of A's and B's matches was recorded first, from the ratings of the match written
  // before; the other from the first's ratings after, whichever server it was on.
  const bool a_first =
      result_of(b, names[0]).rating_before() == result_of(a, names[0]).rating_after();
  const wire::MatchResults& first = a_first ? a : b;
  const wire::MatchResults& second = a_first ? b : a;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    EXPECT_EQ(result_of(first, name).rating_before(), seeded[i]) << name;
    EXPECT_NE(result_of(first, name).rating_after(), seeded[i]) << name;
    EXPECT_EQ(result_of(second, name).rating_before(), result_of(first, name).rating_after())
        << name << " (a lost update: both servers moved the same rating)";
    EXPECT_EQ(result_of(c, name).rating_before(), result_of(second, name).rating_after()) << name;
  }
  // C ranks the two on the one leaderboard: the better rating after its match first.
  const auto& x = result_of(c, names[0]);
  const auto& y = result_of(c, names[1]);
  EXPECT_EQ(x.rank(), x.rating_after() >= y.rating_after() ? 1u : 2u);
  EXPECT_EQ(y.rank(), y.rating_after() >= x.rating_after() ? 1u : 2u);
  EXPECT_TRUE(servers.stop()) << servers.logs();

  // The database holds the four matches and C's ratings after them.
  auto store = db::open_store({.url_or_path = url});
  ASSERT_TRUE(store.ok()) << store.error().message;
  EXPECT_EQ(store.value()->match_count().value(), 4);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto stats = store.value()->player_stats(ids[i]);
    ASSERT_TRUE(stats.ok()) << names[i];
    EXPECT_EQ(stats.value().matches, 4) << names[i];
    EXPECT_EQ(stats.value().rating, result_of(c, names[i]).rating_after()) << names[i];
  }
  if (HasFailure()) std::cout << servers.logs();
}

}  // namespace
}  // namespace ricochet::test::multi_server_test
