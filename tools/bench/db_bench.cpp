/// db-bench: what the database costs, on a real SQLite file in a temporary directory.
///
///   1. seeds --accounts accounts (Minimum-cost hashes: seeding is not what is measured)
///   2. records --matches matches of --players players each (match writes/s: one transaction
///      per match with results, stats and Elo updates)
///   3. logs in --logins times at Argon2id interactive cost (logins/s: dominated by Argon2id)
///   4. checks --token-checks session tokens (token checks/s: one SHA-256 and one indexed read)
///   5. leaderboard latency p50/p99: top 10 and top 100 per board, and a random account's rank
///
/// Prints one JSON line per measurement and a summary line.
///
///   db-bench [--accounts 100000] [--matches 20000] [--players 10] [--logins 20]
///            [--token-checks 20000] [--queries 2000] [--dir DIR]

#include <stdlib.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "ricochet/db/accounts.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"

namespace db = ricochet::db;

namespace {

using Clock = std::chrono::steady_clock;
constexpr db::UnixMillis kT0 = 1'700'000'000'000;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

template <class T>
T must(db::DbResult<T> r, const char* what) {
  if (!r.ok()) {
    std::fprintf(stderr, "db-bench: %s failed: %s: %s\n", what, db::to_string(r.error().code),
                 r.error().message.c_str());
    std::exit(1);
  }
  return std::move(r).value();
}

/// p-th percentile (0..100) of the samples, in microseconds.
double percentile_us(std::vector<double> seconds, double p) {
  if (seconds.empty()) return 0;
  std::sort(seconds.begin(), seconds.end());
  const auto k = static_cast<std::size_t>(p / 100 * static_cast<double>(seconds.size() - 1) + 0.5);
  return seconds[std::min(k, seconds.size() - 1)] * 1e6;
}

const char* board_name(db::LeaderboardKind k) {
  switch (k) {
    case db::LeaderboardKind::Rating:
      return "rating";
    case db::LeaderboardKind::Kills:
      return "kills";
    case db::LeaderboardKind::WinRate:
      return "win_rate";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("db-bench: logins, token checks, match writes and leaderboard latency on SQLite");
  int accounts = 100'000, matches = 20'000, players = 10, logins = 20, token_checks = 20'000,
      queries = 2'000;
  std::string dir;
  app.add_option("--accounts", accounts, "accounts to seed")->check(CLI::Range(10, 10'000'000));
  app.add_option("--matches", matches, "matches to record")->check(CLI::Range(1, 10'000'000));
  app.add_option("--players", players, "players per match")->check(CLI::Range(2, 64));
  app.add_option("--logins", logins, "Argon2id interactive logins")->check(CLI::Range(1, 10'000));
  app.add_option("--token-checks", token_checks, "session checks")
      ->check(CLI::Range(1, 10'000'000));
  app.add_option("--queries", queries, "leaderboard queries per kind")
      ->check(CLI::Range(1, 1'000'000));
  app.add_option("--dir", dir, "directory for the database file (default: a new temp dir)");
  CLI11_PARSE(app, argc, argv);
  if (players > accounts) {
    std::fprintf(stderr, "db-bench: --players must be at most --accounts\n");
    return 2;
  }

  bool remove_dir = false;
  if (dir.empty()) {
    std::string pattern = (std::filesystem::temp_directory_path() / "db-bench-XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      std::fprintf(stderr, "db-bench: cannot create a temp dir\n");
      return 1;
    }
    dir = pattern;
    remove_dir = true;
  }
  const std::string path = (std::filesystem::path(dir) / "bench.db").string();
  std::filesystem::remove(path);
  std::unique_ptr<db::Store> store = must(db::open_sqlite_store({.path = path}), "open");
  db::AccountsOptions fast;
  fast.cost = db::PasswordCost::Minimum;
  db::Accounts seeding(*store, fast);
  db::MatchesOptions boards;
  boards.min_matches_for_win_rate = 3;
  db::Matches matches_rules(*store, boards);

  // 1. Accounts.
  std::vector<db::AccountId> ids;
  ids.reserve(static_cast<std::size_t>(accounts));
  auto start = Clock::now();
  for (int i = 0; i < accounts; ++i)
    ids.push_back(must(seeding.register_account("player" + std::to_string(i), "correct horse", kT0),
                       "register"));
  const double seed_s = seconds_since(start);
  std::printf(
      "{\"bench\":\"db\",\"measure\":\"seed_accounts\",\"accounts\":%d,\"seconds\":%.3f,"
      "\"per_second\":%.1f,\"note\":\"Minimum-cost hashes\"}\n",
      accounts, seed_s, accounts / seed_s);

  // 2. Matches.
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<std::size_t> pick(0, ids.size() - 1);
  std::uniform_int_distribution<int> stat(0, 30);
  std::vector<double> write_s;
  write_s.reserve(static_cast<std::size_t>(matches));
  start = Clock::now();
  for (int m = 0; m < matches; ++m) {
    db::MatchRecord match;
    match.map = "arena";
    match.mode = "ffa";
    match.started_ms = kT0 + m * 600'000LL;
    match.ended_ms = match.started_ms + 600'000;
    std::vector<db::AccountId> chosen;
    while (static_cast<int>(chosen.size()) < players) {
      const db::AccountId id = ids[pick(rng)];
      if (std::find(chosen.begin(), chosen.end(), id) == chosen.end()) chosen.push_back(id);
    }
    for (const db::AccountId id : chosen) {
      db::PlayerResult p;
      p.account = id;
      p.kills = stat(rng);
      p.deaths = stat(rng);
      p.score = p.kills * 100 + p.hits;
      p.shots = 100 + stat(rng) * 10;
      p.hits = stat(rng) * 2;
      p.damage_dealt = p.hits * 25.0;
      p.damage_taken = p.deaths * 100.0;
      p.seconds_played = 600;
      match.players.push_back(p);
    }
    const auto t = Clock::now();
    must(matches_rules.record_match(match), "record_match");
    write_s.push_back(seconds_since(t));
  }
  const double match_s = seconds_since(start);
  std::printf(
      "{\"bench\":\"db\",\"measure\":\"match_writes\",\"matches\":%d,\"players\":%d,"
      "\"per_second\":%.1f,\"p50_us\":%.1f,\"p99_us\":%.1f}\n",
      matches, players, matches / match_s, percentile_us(write_s, 50), percentile_us(write_s, 99));

  // 3. Logins at the production cost.
  db::Accounts live(*store, db::AccountsOptions{});
  must(live.register_account("bench_user", "correct horse battery", kT0), "register");
  std::vector<std::string> tokens;
  std::vector<double> login_s;
  start = Clock::now();
  for (int i = 0; i < logins; ++i) {
    const auto t = Clock::now();
    tokens.push_back(
        must(live.login("bench_user", "correct horse battery", "", kT0 + i), "login").token);
    login_s.push_back(seconds_since(t));
  }
  const double logins_per_s = logins / seconds_since(start);
  std::printf(
      "{\"bench\":\"db\",\"measure\":\"logins\",\"cost\":\"argon2id_interactive\","
      "\"logins\":%d,\"per_second\":%.2f,\"p50_ms\":%.2f,\"p99_ms\":%.2f}\n",
      logins, logins_per_s, percentile_us(login_s, 50) / 1000, percentile_us(login_s, 99) / 1000);

  // 4. Token checks.
  std::vector<double> check_s;
  check_s.reserve(static_cast<std::size_t>(token_checks));
  start = Clock::now();
  for (int i = 0; i < token_checks; ++i) {
    const auto t = Clock::now();
    must(live.check_session(tokens[static_cast<std::size_t>(i) % tokens.size()], kT0 + 1000),
         "check_session");
    check_s.push_back(seconds_since(t));
  }
  const double checks_per_s = token_checks / seconds_since(start);
  std::printf(
      "{\"bench\":\"db\",\"measure\":\"token_checks\",\"checks\":%d,\"per_second\":%.1f,"
      "\"p50_us\":%.1f,\"p99_us\":%.1f}\n",
      token_checks, checks_per_s, percentile_us(check_s, 50), percentile_us(check_s, 99));

  // 5. Leaderboards.
  double worst_p99_us = 0;
  for (const db::LeaderboardKind kind :
       {db::LeaderboardKind::Rating, db::LeaderboardKind::Kills, db::LeaderboardKind::WinRate}) {
    for (const int limit : {10, 100}) {
      std::vector<double> s;
      for (int q = 0; q < queries; ++q) {
        const auto t = Clock::now();
        const auto board = must(matches_rules.leaderboard(kind, limit), "leaderboard");
        s.push_back(seconds_since(t));
        if (board.empty()) {
          std::fprintf(stderr, "db-bench: empty %s board\n", board_name(kind));
          return 1;
        }
      }
      worst_p99_us = std::max(worst_p99_us, percentile_us(s, 99));
      std::printf(
          "{\"bench\":\"db\",\"measure\":\"leaderboard_top\",\"board\":\"%s\","
          "\"limit\":%d,\"accounts\":%d,\"p50_us\":%.1f,\"p99_us\":%.1f}\n",
          board_name(kind), limit, accounts, percentile_us(s, 50), percentile_us(s, 99));
    }
    std::vector<double> s;
    for (int q = 0; q < queries; ++q) {
      const db::AccountId id = ids[pick(rng)];
      const auto t = Clock::now();
      (void)must(matches_rules.rank_of(id, kind), "rank_of");
      s.push_back(seconds_since(t));
    }
    worst_p99_us = std::max(worst_p99_us, percentile_us(s, 99));
    std::printf(
        "{\"bench\":\"db\",\"measure\":\"rank_of\",\"board\":\"%s\",\"accounts\":%d,"
        "\"p50_us\":%.1f,\"p99_us\":%.1f}\n",
        board_name(kind), accounts, percentile_us(s, 50), percentile_us(s, 99));
  }
  std::printf(
      "{\"bench\":\"db\",\"summary\":true,\"accounts\":%d,\"logins_per_s\":%.2f,"
      "\"token_checks_per_s\":%.1f,\"match_writes_per_s\":%.1f,"
      "\"leaderboard_worst_p99_us\":%.1f}\n",
      accounts, logins_per_s, checks_per_s, matches / match_s, worst_p99_us);
  store.reset();
  if (remove_dir) std::filesystem::remove_all(dir);
  return 0;
}
