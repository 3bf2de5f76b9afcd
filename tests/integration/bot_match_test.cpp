// End to end with nothing in-process but the bot: the real ricochet-server binary runs as a
// child process on 127.0.0.1 (ports chosen free, a temporary data directory, a fixed seed), and
// ricochet_bot plays it over real sockets. Every wait is bounded; the tests assert outcomes
// (results, the database, exit codes), never speeds.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <sys/wait.h>

#include "ricochet/bot/bot.h"
#include "ricochet/bot/fleet.h"
#include "ricochet/db/store.h"
#include "server_process.h"

namespace ricochet::test {
namespace {

using namespace std::chrono_literals;
namespace asio = boost::asio;

/// The [matches] table: one free-for-all match on the arena, no warm-up, no frag limit, seeded,
/// recorded when `record`.
std::string matches_toml(int min_players, double time_limit_s, bool record = false) {
  std::string toml = "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
                     "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\n";
  toml += record ? "record = true\n" : "record = false\n";
  toml += "min_players = ";
  toml += std::to_string(min_players);
  toml += "\ntime_limit_s = ";
  toml += std::to_string(time_limit_s);
  toml += '\n';
  return toml;
}

bot::BotConfig bot_config(const ServerProcess& server, const std::string& name) {
  bot::BotConfig config;
  config.host = "127.0.0.1";
  config.control_port = server.control_port();
  config.fingerprint = server.fingerprint();
  config.name = name;
  config.password = "password-of-" + name;
  config.skill = 0.9;
  config.matches = 1;
  return config;
}

/// Runs `io` until `done()` holds or `limit` passes; whether it holds.
template <class Done>
bool run_until(asio::io_context& io, Done done, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    io.run_for(20ms);
    if (io.stopped()) io.restart();
  }
  return true;
}

const wire::PlayerMatchResult* result_of(const wire::MatchResults& results, std::uint64_t account) {
  for (const wire::PlayerMatchResult& player : results.players()) {
    if (player.account_id() == account) return &player;
  }
  return nullptr;
}

const wire::PlayerScore* score_of(const wire::MatchState& state, std::uint32_t entity) {
  for (const wire::PlayerScore& score : state.scores()) {
    if (score.entity_id() == entity) return &score;
  }
  return nullptr;
}

/// `ricochet-replay --json FILE`: its exit code and what it printed.
std::pair<int, std::string> replay(const std::filesystem::path& file) {
  const std::string command =
      std::string(RICOCHET_REPLAY_BINARY) + " --json '" + file.string() + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  char chunk[4096];
  while (const std::size_t size = std::fread(chunk, 1, sizeof chunk, pipe)) output.append(chunk, size);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

/// The number after `"key":` in the replay's score object of `account` (-1 when absent).
long long replay_score(const std::string& json, std::uint64_t account, const std::string& key) {
  const auto at = json.find("{\"account\":" + std::to_string(account) + ",");
  if (at == std::string::npos) return -1;
  const auto field = json.find("\"" + key + "\":", at);
  if (field == std::string::npos) return -1;
  return std::stoll(json.substr(field + key.size() + 3));
}

std::unique_ptr<db::Store> open_database(const std::filesystem::path& path) {
  auto store = db::open_sqlite_store({.path = path.string()});
  if (!store.ok()) return nullptr;
  return std::move(store).value();
}

TEST(BotMatch, EightBotsPlayToTheTimeLimitAndTheResultsMatchTheKillsTheySaw) {
  ServerProcess server(matches_toml(8, 10.0, /*record=*/true));
  ASSERT_TRUE(server.wait_listening()) << server.log();
  asio::io_context io;
  bot::FleetConfig config;
  config.bot = bot_config(server, "eight");
  config.bots = 8;
  bot::Fleet fleet(io, config);
  fleet.start();
  ASSERT_TRUE(run_until(
      io, [&] { return fleet.done(); }, 50s))
      << fleet.report_json();
  std::cout << "[ figures  ] " << fleet.report_json() << std::endl;
  server.terminate();
  ASSERT_EQ(server.wait_exit(25s), std::optional<int>(0)) << server.log();

  const bot::BotRecord& reference = fleet.bots().front()->record();
  ASSERT_EQ(reference.results.size(), 1u);
  int kills_of_players = 0;  // every Kill event between two players (not a suicide or the world)
  for (const wire::Kill& kill : reference.kills) {
    if (kill.killer_entity_id() != 0 && kill.killer_entity_id() != kill.victim_entity_id()) {
      ++kills_of_players;
    }
  }
  int kills_in_results = 0;
  for (const wire::PlayerMatchResult& player : reference.results[0].players()) {
    kills_in_results += player.kills();
  }
  EXPECT_EQ(kills_in_results, kills_of_players);

  auto store = open_database(server.db_path());
  ASSERT_TRUE(store);
  for (const auto& each : fleet.bots()) {
    const std::string& name = each->config().name;
    const bot::BotRecord& record = each->record();
    const bot::BotMetrics metrics = each->metrics();
    EXPECT_TRUE(record.error.empty()) << name << ": " << record.error;
    ASSERT_EQ(record.results.size(), 1u) << name;
    const wire::MatchResults& results = record.results[0];
    EXPECT_FALSE(results.aborted()) << name;
    EXPECT_EQ(results.end_reason(), wire::MATCH_END_REASON_TIME_LIMIT) << name;
    EXPECT_EQ(results.players_size(), 8) << name;
    EXPECT_EQ(record.match_ended,
              std::vector<wire::MatchEndReason>{wire::MATCH_END_REASON_TIME_LIMIT})
        << name;
    const wire::PlayerMatchResult* mine = result_of(results, record.account_id);
    ASSERT_NE(mine, nullptr) << name;
    EXPECT_EQ(mine->kills(), metrics.kills) << name;
    EXPECT_EQ(mine->deaths(), metrics.deaths) << name;
    // Every bot saw the same Kill events, in the same order.
    ASSERT_EQ(record.kills.size(), reference.kills.size()) << name;
    for (std::size_t i = 0; i < record.kills.size(); ++i) {
      EXPECT_EQ(record.kills[i].SerializeAsString(), reference.kills[i].SerializeAsString())
          << name << " kill " << i;
    }
    EXPECT_GT(metrics.snapshots, 0u) << name;
    EXPECT_EQ(metrics.snapshots_refused, 0u) << name;
    EXPECT_EQ(metrics.bad_payloads, 0u) << name;
    EXPECT_EQ(metrics.bad_events, 0u) << name;
    // The database holds the same results (the server has exited: the file is ours).
    const auto stats = store->player_stats(static_cast<db::AccountId>(record.account_id));
    ASSERT_TRUE(stats.ok()) << name;
    EXPECT_EQ(stats.value().matches, 1) << name;
    EXPECT_EQ(stats.value().kills, mine->kills()) << name;
    EXPECT_EQ(stats.value().deaths, mine->deaths()) << name;
  }
  const auto matches = store->match_count();
  ASSERT_TRUE(matches.ok());
  EXPECT_GE(matches.value(), 1);

  // The match's recording (the one match played: the next of the rotation, which nobody
  // joined, keeps none) replays bit-exactly with ricochet-replay, to the same scores.
  std::vector<std::filesystem::path> recordings;
  for (const auto& entry : std::filesystem::directory_iterator(server.dir() / "data" / "recordings")) {
    if (entry.path().extension() == ".rcr") recordings.push_back(entry.path());
  }
  ASSERT_EQ(recordings.size(), 1u);
  const auto [exit_code, json] = replay(recordings[0]);
  EXPECT_EQ(exit_code, 0) << json;
  EXPECT_NE(json.find("\"complete\":true"), std::string::npos) << json;
  EXPECT_NE(json.find("\"hashes_differing\":0,"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"hashes_checked\":0,"), std::string::npos) << json;
  for (const auto& each : fleet.bots()) {
    const wire::PlayerMatchResult* mine = result_of(each->record().results.at(0), each->record().account_id);
    ASSERT_NE(mine, nullptr);
    EXPECT_EQ(replay_score(json, each->record().account_id, "kills"), mine->kills()) << json;
    EXPECT_EQ(replay_score(json, each->record().account_id, "deaths"), mine->deaths()) << json;
  }
  if (HasFailure()) std::cout << "server log:\n" << server.log();
}

TEST(BotMatch, ABotThatReconnectsFromAnotherPortKeepsItsScore) {
  ServerProcess server(matches_toml(2, 14.0));
  ASSERT_TRUE(server.wait_listening()) << server.log();
  asio::io_context io;
  auto tls = bot::make_control_tls_context();
  auto trust = bot::ServerTrust::pinned(server.fingerprint());
  bot::BotConfig mover_config = bot_config(server, "mover");
  mover_config.rebind_after_s = 5;
  bot::Bot mover(io, tls, trust, mover_config);
  bot::Bot stayer(io, tls, trust, bot_config(server, "stayer"));
  mover.start();
  stayer.start();
  ASSERT_TRUE(run_until(
      io,
      [&] { return mover.state() == bot::BotState::Done && stayer.state() == bot::BotState::Done; },
      50s));
  std::cout << "[ figures  ] mover " << mover.metrics().to_json() << std::endl;
  server.terminate();
  ASSERT_EQ(server.wait_exit(25s), std::optional<int>(0)) << server.log();

  const bot::BotRecord& record = mover.record();
  EXPECT_TRUE(record.error.empty()) << record.error;
  // At least two game connections, each from its own local port, on the same entity.
  ASSERT_GE(record.local_ports.size(), 2u);
  for (std::size_t i = 1; i < record.local_ports.size(); ++i) {
    EXPECT_NE(record.local_ports[i], record.local_ports[i - 1]);
  }
  EXPECT_GE(mover.metrics().reconnects, 1);
  ASSERT_GE(record.entity_ids.size(), 2u);
  for (const std::uint32_t entity : record.entity_ids) EXPECT_EQ(entity, record.entity_ids[0]);
  // On each arrival after the first, the server's score for the entity is what the bot had
  // counted from the Kill events before it moved.
  ASSERT_GE(record.arrivals.size(), 2u);
  for (std::size_t i = 1; i < record.arrivals.size(); ++i) {
    const bot::BotRecord::Arrival& arrival = record.arrivals[i];
    const wire::PlayerScore* score = score_of(arrival.state, record.entity_ids[0]);
    ASSERT_NE(score, nullptr) << "arrival " << i << ": " << arrival.state.DebugString();
    EXPECT_EQ(score->kills(), arrival.kills_counted) << "arrival " << i;
    EXPECT_EQ(score->deaths(), arrival.deaths_counted) << "arrival " << i;
    EXPECT_EQ(score->score(), arrival.score_counted) << "arrival " << i;
    std::cout << "[ figures  ] arrival " << i << ": kills " << score->kills() << ", deaths "
              << score->deaths() << ", score " << score->score() << std::endl;
  }
  // The results count the whole match, across the moves.
  ASSERT_EQ(record.results.size(), 1u);
  EXPECT_FALSE(record.results[0].aborted());
  EXPECT_EQ(record.results[0].players_size(), 2);
  const wire::PlayerMatchResult* mine = result_of(record.results[0], record.account_id);
  ASSERT_NE(mine, nullptr);
  EXPECT_EQ(mine->kills(), mover.metrics().kills);
  EXPECT_EQ(mine->deaths(), mover.metrics().deaths);
}

TEST(BotMatch, SigtermDuringAMatchExitsZeroAndRecordsTheAbortedMatch) {
  ServerProcess server(matches_toml(4, 120.0));
  ASSERT_TRUE(server.wait_listening()) << server.log();
  asio::io_context io;
  bot::FleetConfig config;
  config.bot = bot_config(server, "stopped");
  config.bot.max_reconnect_attempts = 2;
  config.bots = 4;
  bot::Fleet fleet(io, config);
  fleet.start();
  const auto everyone_sees_the_match = [&] {
    for (const auto& each : fleet.bots()) {
      if (each->state() != bot::BotState::Playing || each->metrics().snapshots == 0) return false;
    }
    return true;
  };
  ASSERT_TRUE(run_until(io, everyone_sees_the_match, 40s)) << fleet.report_json();
  run_until(
      io, [] { return false; }, 2s);  // play a little
  server.terminate();
  std::optional<int> exit_code;
  run_until(
      io, [&] { return (exit_code = server.wait_exit(0ms)).has_value(); }, 25s);
  fleet.stop("the server is gone");
  ASSERT_TRUE(run_until(
      io, [&] { return fleet.done(); }, 5s));
  ASSERT_EQ(exit_code, std::optional<int>(0)) << server.log();

  for (const auto& each : fleet.bots()) {
    const bot::BotRecord& record = each->record();
    EXPECT_EQ(record.match_ended,
              std::vector<wire::MatchEndReason>{wire::MATCH_END_REASON_SERVER_SHUTDOWN})
        << each->config().name;
    // The results come over the control channel before the server closes it.
    ASSERT_EQ(record.results.size(), 1u) << each->config().name;
    EXPECT_TRUE(record.results[0].aborted()) << each->config().name;
    EXPECT_EQ(record.results[0].end_reason(), wire::MATCH_END_REASON_SERVER_SHUTDOWN);
    EXPECT_EQ(record.results[0].players_size(), 4);
    const wire::PlayerMatchResult* mine = result_of(record.results[0], record.account_id);
    ASSERT_NE(mine, nullptr) << each->config().name;
    EXPECT_EQ(mine->rating_after(), mine->rating_before()) << each->config().name;
  }
  auto store = open_database(server.db_path());
  ASSERT_TRUE(store);
  const auto matches = store->match_count();
  ASSERT_TRUE(matches.ok());
  EXPECT_GE(matches.value(), 1);
  for (const auto& each : fleet.bots()) {
    const auto stats = store->player_stats(static_cast<db::AccountId>(each->record().account_id));
    ASSERT_TRUE(stats.ok());
    // Recorded (the match counts in the lifetime totals) and aborted (no winner, no rating move).
    EXPECT_EQ(stats.value().matches, 1) << each->config().name;
    EXPECT_EQ(stats.value().wins, 0) << each->config().name;
    EXPECT_EQ(stats.value().rating, 1500) << each->config().name;
    EXPECT_GT(stats.value().seconds_played, 0) << each->config().name;
  }
}

TEST(BotMatch, TrustOnFirstUseWritesTheFingerprintAndRefusesAnotherLater) {
  ServerProcess server(matches_toml(1, 60.0));
  ASSERT_TRUE(server.wait_listening()) << server.log();
  asio::io_context io;
  auto tls = bot::make_control_tls_context();

  const std::filesystem::path trust_file = server.dir() / "trusted-server";
  bot::BotConfig first_config = bot_config(server, "first");
  first_config.fingerprint.clear();
  first_config.trust_file = trust_file.string();
  auto first_use = bot::ServerTrust::on_first_use(trust_file);
  bot::Bot first(io, tls, first_use, first_config);
  first.start();
  ASSERT_TRUE(run_until(
      io, [&] { return first.state() == bot::BotState::Playing; }, 20s));
  std::ifstream written(trust_file);
  std::string line;
  std::getline(written, line);
  EXPECT_EQ(line, server.fingerprint());
  first.stop("test over");

  // A file that trusts another certificate: the bot refuses the server before signing in.
  const std::filesystem::path other_file = server.dir() / "trusted-elsewhere";
  std::string other;
  for (int i = 0; i < 32; ++i) other += i ? ":AB" : "AB";
  std::ofstream(other_file) << other << "\n";
  bot::BotConfig second_config = first_config;
  second_config.name = "second";
  second_config.trust_file = other_file.string();
  auto elsewhere = bot::ServerTrust::on_first_use(other_file);
  bot::Bot second(io, tls, elsewhere, second_config);
  second.start();
  ASSERT_TRUE(run_until(
      io, [&] { return second.state() == bot::BotState::Done; }, 20s));
  EXPECT_NE(second.record().error.find("is not the trusted"), std::string::npos)
      << second.record().error;
  EXPECT_EQ(second.record().account_id, 0u);

  server.terminate();
  EXPECT_EQ(server.wait_exit(25s), std::optional<int>(0)) << server.log();
}

}  // namespace
}  // namespace ricochet::test
