// Placement with bots (issue 31, section 2): three real ricochet-server processes on one
// PostgreSQL database, A hosting free-for-all only, B and C team deathmatch only. Bots that
// know only A ask it for tdm (ricochet-bot --find-match tdm) and are sent to B and C, follow
// their assignments there (the certificate pinned from the assignment, the session resumed, the
// ticket presented), play their match to its time limit and see its results; a bot that knows
// only C asks for ffa, plays on A, and for its second match asks C again and plays on A again.
// Prints the figures of the run. Every wait is bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <iostream>
#include <map>
#include <memory>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "admin_get.h"
#include "ctest_budget.h"
#include "postgres_cluster.h"
#include "ricochet/bot/bot.h"
#include "ricochet/bot/fleet.h"
#include "ricochet/db/store.h"
#include "ricochet/stats/summary.h"
#include "run_until.h"
#include "server_process.h"

namespace ricochet::test::bot_placement_test {
namespace {

using namespace std::chrono_literals;
namespace asio = boost::asio;

/// From the forks to the three ports files and directory rows (the servers start at once).
constexpr std::chrono::seconds kStartBudget{10};
/// Every match's time limit: matches end by themselves, soon.
constexpr std::chrono::seconds kTimeLimit{2};
/// The bots sign in, are placed (with the retries of a seat taken under them), play a match of
/// kTimeLimit and get its results; the ffa bot two.
constexpr std::chrono::seconds kPlayBudget{2 * kTimeLimit + 15s};
constexpr int kShutdownGraceS = 5;
constexpr std::chrono::seconds kExitBudget{kShutdownGraceS + 3};

constexpr int kTdmBots = 12;
/// B's and C's tdm matches each: 16 seats for 12 bots, so that filling (fullest first) and
/// spreading (3 to each match) give different matches.
constexpr int kMatchesPerServer = 2;
constexpr int kSeatsPerMatch = 4;

/// `count` matches of `mode` on the arena, each ending at kTimeLimit, started by one player
/// (a bot that came alone still plays to the end).
std::string matches_toml(const std::string& mode, int count) {
  return "count = " + std::to_string(count) + "\nmax_players = " + std::to_string(kSeatsPerMatch) +
         "\nmode = \"" + mode +
         "\"\nmaps = [\"" RICOCHET_SOURCE_DIR
         "/server/maps/arena.toml\"]\nseed = 7\nwarmup_s = 0\nfrag_limit = 0\nrecord = false\n"
         "min_players = 1\ntime_limit_s = " +
         std::to_string(kTimeLimit.count()) + "\n";
}

/// On `url`, placement on with the shortest heartbeat, the minimum password cost.
std::string fleet_toml(const std::string& url) {
  return "[db]\nurl = \"" + url +
         "\"\npassword_hashing = \"minimum\"\nregistrations_per_hour_per_address = 100\n"
         "[placement]\nadvertise_host = \"127.0.0.1\"\nheartbeat_s = 1\nserver_ttl_s = 5\n";
}

/// Whether the server logged that its directory row was written, within `limit`.
bool listed(const ServerProcess& server, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (server.log().find("is in the fleet directory") == std::string::npos) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}
/// ricochet_placement_tickets_total by result, as "assigned=N ..." (results with 0 left out).
std::string tickets_of(const ServerProcess& server) {
  const std::string page = ricochet::test::admin_get(server.admin_port(), "/metrics");
  const std::regex line(
      R"re(ricochet_placement_tickets_total\{result="([a-z_]+)"\} ([0-9.e+]+))re");
  std::string text;
  for (auto it = std::sregex_iterator(page.begin(), page.end(), line); it != std::sregex_iterator();
       ++it) {
    if (std::stod((*it)[2].str()) == 0) continue;
    text += (*it)[1].str() + "=" + (*it)[2].str() + " ";
  }
  return text;
}

std::string control_of(const ServerProcess& server) {
  return "127.0.0.1:" + std::to_string(server.control_port());
}

TEST(BotPlacement, BotsThatKnowOneServerArePlacedOnTheOthersFullestMatchFirstAndPlayThere) {
  static_assert(fits_ctest(kStartBudget + kPlayBudget + kExitBudget));
  const std::string url = PostgresCluster::shared().create_database();
  ServerProcess a(matches_toml("ffa", 1), kShutdownGraceS, fleet_toml(url));
  ServerProcess b(matches_toml("tdm", kMatchesPerServer), kShutdownGraceS, fleet_toml(url));
  ServerProcess c(matches_toml("tdm", kMatchesPerServer), kShutdownGraceS, fleet_toml(url));
  const auto logs = [&] {
    return "--- A:\n" + a.log() + "--- B:\n" + b.log() + "--- C:\n" + c.log();
  };
  for (ServerProcess* server : {&a, &b, &c}) {
    ASSERT_TRUE(server->wait_listening(kStartBudget)) << logs();
  }
  for (ServerProcess* server : {&a, &b, &c}) ASSERT_TRUE(listed(*server, kStartBudget)) << logs();

  asio::io_context io;
  bot::FleetConfig tdm;
  tdm.bots = kTdmBots;
  tdm.bot.control_port = a.control_port();
  tdm.bot.fingerprint = a.fingerprint();  // A's only: B's and C's come with the assignments
  tdm.bot.name = "placed";
  tdm.bot.find_match = "tdm";
  tdm.bot.matches = 1;
  tdm.bot.predict = false;
  tdm.bind_addresses = {"127.0.0.2", "127.0.0.3", "127.0.0.4"};  // within per-address limits
  ASSERT_EQ(tdm.validate(), "");
  bot::Fleet fleet(io, tdm);
  // The refusals the tdm bots answered by finding again (Bot::on_failure).
  std::vector<std::string> refusals;
  for (const auto& each : fleet.bots()) {
    each->on_failure([&](std::string_view reason) { refusals.emplace_back(reason); });
  }

  bot::BotConfig ffa_config;
  ffa_config.control_port = c.control_port();
  ffa_config.fingerprint = c.fingerprint();
  ffa_config.name = "wanderer";
  ffa_config.find_match = "ffa";
  ffa_config.matches = 2;
  ffa_config.predict = false;
  ffa_config.bind_address = "127.0.0.5";
  ASSERT_EQ(ffa_config.validate(), "");
  auto ffa_trust = bot::ServerTrust::pinned(c.fingerprint());
  auto tls = bot::make_control_tls_context();
  bot::Bot wanderer(io, tls, ffa_trust, ffa_config);

  const auto started = std::chrono::steady_clock::now();
  ASSERT_EQ(fleet.start(), "");
  wanderer.start();
  const bool finished = run_until(
      io, [&] { return fleet.done() && wanderer.state() == bot::BotState::Done; }, kPlayBudget);
  const double played_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::vector<const bot::Bot*> everyone;
  for (const auto& each : fleet.bots()) everyone.push_back(each.get());
  everyone.push_back(&wanderer);
  std::string errors;
  for (const bot::Bot* each : everyone) {
    if (!each->record().error.empty())
      errors += each->config().name + ": " + each->record().error + "\n";
  }
  ASSERT_TRUE(finished) << errors << fleet.report_json() << logs();
  ASSERT_EQ(errors, "") << logs();

  // Each tdm bot was placed once, on B or C, and played that match to its time limit.
  std::map<std::string, int> bots_on;                            ///< by server control channel
  std::map<std::pair<std::string, std::uint32_t>, int> bots_in;  ///< by server and match
  std::vector<double> placement_ms;
  for (const auto& each : fleet.bots()) {
    const bot::BotRecord& record = each->record();
    const std::string& name = each->config().name;
    ASSERT_EQ(record.placements.size(), 1u) << name;
    const bot::BotRecord::Placement& placed = record.placements[0];
    EXPECT_TRUE(placed.server == control_of(b) || placed.server == control_of(c))
        << name << " placed on " << placed.server;
    ++bots_on[placed.server];
    ++bots_in[{placed.server, placed.match_id}];
    ASSERT_EQ(record.results.size(), 1u) << name;
    EXPECT_EQ(record.results[0].match_id(), placed.match_id) << name;
    EXPECT_EQ(record.results[0].mode(), "tdm") << name;
    EXPECT_FALSE(record.results[0].aborted()) << name;
    ASSERT_EQ(record.match_ended.size(), 1u) << name;
    EXPECT_EQ(record.match_ended[0], wire::MATCH_END_REASON_TIME_LIMIT) << name;
    const bot::BotMetrics metrics = each->metrics();
    ASSERT_EQ(metrics.placement_ms.size(), 1u) << name;
    placement_ms.push_back(metrics.placement_ms[0]);
  }
  EXPECT_EQ(bots_on.size(), 2u) << "B and C both take bots";
  // A ticket is refused only by the hosting server's own bound on players still connecting to
  // one match (half its seats: 2 of 4, the hardening's reservation bound), when a slow machine
  // leaves three placed bots connecting at once; never because placement gave a seat that was
  // taken (MATCH_FULL "seats taken"): a claimed ticket holds its seat until its server's
  // heartbeat counts the player. (When the claim let the seat go, the burst piled onto one
  // match: 36 tickets for 12 bots, 2 to 3 full matches.)
  int still_connecting = 0;
  for (const std::string& reason : refusals) {
    const bool bound = reason.find("still connecting") != std::string::npos;
    EXPECT_TRUE(bound) << "a refusal placement should have prevented: " << reason;
    still_connecting += bound;
  }
  // Fullest first: a match takes players until it is full before the next one does, so the 12
  // fill three matches (spreading would fill none: 3 each); a bot refused by the bound finds
  // again after the others went on, and can leave one match a seat short.
  int full_matches = 0;
  for (const auto& [where, bots] : bots_in) {
    EXPECT_LE(bots, kSeatsPerMatch);
    full_matches += bots == kSeatsPerMatch;
  }
  EXPECT_GE(full_matches, kTdmBots / kSeatsPerMatch - still_connecting)
      << "bots per match: " << ::testing::PrintToString(bots_in);

  // The ffa bot that knew only C plays on A, twice: after its first match it asked C again
  // (C's tickets below are its two).
  ASSERT_EQ(wanderer.record().placements.size(), 2u);
  ASSERT_EQ(wanderer.record().results.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(wanderer.record().placements[i].server, control_of(a)) << i;
    EXPECT_EQ(wanderer.record().results[i].mode(), "ffa") << i;
    EXPECT_EQ(wanderer.record().results[i].match_id(), wanderer.record().placements[i].match_id);
  }
  ASSERT_EQ(wanderer.metrics().placement_ms.size(), 2u);
  placement_ms.push_back(wanderer.metrics().placement_ms[0]);

  // The figures of the run, for a note.
  const stats::Summary placement = stats::summarize(placement_ms);
  std::cout << "placement run: " << kTdmBots << " tdm bots through A: " << bots_on[control_of(b)]
            << " on B, " << bots_on[control_of(c)]
            << " on C; bots per match: " << ::testing::PrintToString(bots_in)
            << "; 1 ffa bot through C on A, twice; find_match to first snapshot p50 "
            << placement.p50 << " ms, max " << placement.max << " ms (" << placement.count
            << " bots); tickets A: " << tickets_of(a) << "B: " << tickets_of(b)
            << "C: " << tickets_of(c) << "; refused by the connecting bound " << still_connecting
            << "; bots started to all done " << played_s << " s\n";
  // Every find_match was answered by the server the bot knew: A's tickets are the tdm bots', one
  // each and one more per refusal by the connecting bound (no seat is taken under a ticket), C's
  // the ffa bot's, one a match (a ticket for a match A ended seats it in A's next one, where it
  // used to find again); B answered none.
  const std::regex assigned("^assigned=([0-9]+) $");
  std::smatch count;
  const std::string on_a = tickets_of(a);
  const std::string on_c = tickets_of(c);
  ASSERT_TRUE(std::regex_match(on_a, count, assigned)) << on_a;
  EXPECT_EQ(std::stoi(count[1].str()), kTdmBots + still_connecting);
  ASSERT_TRUE(std::regex_match(on_c, count, assigned)) << on_c;
  EXPECT_EQ(std::stoi(count[1].str()), 2);
  EXPECT_EQ(tickets_of(b), "");

  for (ServerProcess* server : {&a, &b, &c}) server->terminate();
  for (ServerProcess* server : {&a, &b, &c}) {
    EXPECT_EQ(server->wait_exit(kExitBudget), std::optional<int>(0)) << logs();
  }
  // The database holds each bot's matches once each: the tdm matches and the ffa bot's two.
  auto store = db::open_store({.url_or_path = url});
  ASSERT_TRUE(store.ok()) << store.error().message;
  for (const bot::Bot* each : everyone) {
    const auto stats = store.value()->player_stats(each->record().account_id);
    ASSERT_TRUE(stats.ok()) << each->config().name;
    EXPECT_EQ(stats.value().matches, static_cast<std::int64_t>(each->record().results.size()))
        << each->config().name;
  }
  EXPECT_EQ(store.value()->match_count().value(), static_cast<std::int64_t>(bots_in.size() + 2));
  if (HasFailure()) std::cout << logs();
}

TEST(BotPlacement, ABotTheFleetHasNoSeatForWaitsAndSaysWhy) {
  // One server with game clients for two: the third bot's find_match is refused
  // NO_SERVER_AVAILABLE; it waits and asks again (never gives up on it) and reports each refusal
  // (Bot::on_failure), which is how the load test counts the refusals bots answer by themselves.
  constexpr std::chrono::seconds kRefusedBudget{10};
  static_assert(fits_ctest(kStartBudget + kRefusedBudget + kExitBudget));
  const std::string url = PostgresCluster::shared().create_database();
  ServerProcess server("count = 1\nmax_players = 4\nmode = \"tdm\"\nmaps = [\"" RICOCHET_SOURCE_DIR
                       "/server/maps/arena.toml\"]\nwarmup_s = 0\nfrag_limit = 0\n"
                       "record = false\nmin_players = 1\ntime_limit_s = 0\n",
                       kShutdownGraceS, fleet_toml(url), {}, "", "max_clients = 2\n");
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  ASSERT_TRUE(listed(server, kStartBudget)) << server.log();

  asio::io_context io;
  bot::FleetConfig config;
  config.bots = 3;
  config.bot.control_port = server.control_port();
  config.bot.fingerprint = server.fingerprint();
  config.bot.name = "waiting";
  config.bot.find_match = "tdm";
  config.bot.predict = false;
  config.bind_addresses = {"127.0.0.2", "127.0.0.3", "127.0.0.4"};
  ASSERT_EQ(config.validate(), "");
  bot::Fleet fleet(io, config);
  std::vector<std::string> refusals;
  for (const auto& each : fleet.bots()) {
    each->on_failure([&](std::string_view reason) { refusals.emplace_back(reason); });
  }
  const auto playing = [&] {
    int count = 0;
    for (const auto& each : fleet.bots()) count += each->state() == bot::BotState::Playing;
    return count;
  };
  const auto refused = [&] {
    return std::count_if(refusals.begin(), refusals.end(), [](const std::string& reason) {
      return reason.find("NO_SERVER_AVAILABLE") != std::string::npos;
    });
  };
  ASSERT_EQ(fleet.start(), "");
  // Two play; the third is refused, waits about 2 s and is refused again.
  const bool seen = run_until(
      io, [&] { return playing() == 2 && refused() >= 2; }, kRefusedBudget);
  ASSERT_TRUE(seen) << "playing " << playing() << ", refusals "
                    << ::testing::PrintToString(refusals) << "\n"
                    << server.log();
  for (const std::string& reason : refusals) {
    EXPECT_NE(reason.find("find_match: NO_SERVER_AVAILABLE"), std::string::npos) << reason;
  }
  EXPECT_FALSE(fleet.done()) << "a full fleet is not a reason to give up";
  for (const auto& each : fleet.bots()) EXPECT_EQ(each->record().error, "");
  server.terminate();
  EXPECT_EQ(server.wait_exit(kExitBudget), std::optional<int>(0)) << server.log();
}

}  // namespace
}  // namespace ricochet::test::bot_placement_test
