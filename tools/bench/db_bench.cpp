/// db-bench: what the database costs, on a real SQLite file in a temporary directory.
///
///   1. seeds --accounts accounts (Minimum-cost hashes: seeding is not what is measured)
///   2. records --matches matches of --players players each (match writes/s: one transaction
///      per match with results, stats and Elo updates)
///   3. logs in --logins times at Argon2id interactive cost (logins/s: dominated by Argon2id)
///   4. checks --token-checks session tokens (token checks/s: one SHA-256 and one indexed read)
///   5. leaderboard latency p50/p99: top 10 and top 100 per board, and a random account's rank
///
/// Prints one JSON line per measurement and a summary line. Percentiles are nearest rank
/// (ricochet/stats/percentile.h).
///
///   db-bench [--accounts 100000] [--matches 20000] [--players 10] [--logins 20]
///            [--token-checks 20000] [--queries 2000] [--dir DIR] [--out FILE]

#include <stdlib.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "harness.h"
#include "ricochet/db/accounts.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"

namespace db = ricochet::db;
namespace bench = ricochet::bench;
namespace stats = ricochet::stats;

namespace {

constexpr db::UnixMillis kT0 = 1'700'000'000'000;

template <class T>
T must(db::DbResult<T> r, const char* what) {
  if (!r.ok()) {
    std::fprintf(stderr, "db-bench: %s failed: %s: %s\n", what, db::to_string(r.error().code),
                 r.error().message.c_str());
    std::exit(1);
  }
  return std::move(r).value();
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
  std::string dir, out;
  app.add_option("--accounts", accounts, "accounts to seed")->check(CLI::Range(10, 10'000'000));
  app.add_option("--matches", matches, "matches to record")->check(CLI::Range(1, 10'000'000));
  app.add_option("--players", players, "players per match")->check(CLI::Range(2, 64));
  app.add_option("--logins", logins, "Argon2id interactive logins")->check(CLI::Range(1, 10'000));
  app.add_option("--token-checks", token_checks, "session checks")
      ->check(CLI::Range(1, 10'000'000));
  app.add_option("--queries", queries, "leaderboard queries per kind")
      ->check(CLI::Range(1, 1'000'000));
  app.add_option("--dir", dir, "directory for the database file (default: a new temp dir)");
  app.add_option("--out", out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);
  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "db-bench: cannot write %s\n", out.c_str());
    return 2;
  }
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
  bench::Stopwatch seeding_time;
  for (int i = 0; i < accounts; ++i)
    ids.push_back(
        must(seeding.register_account("player" + std::to_string(i), "correct horse", "", kT0),
             "register"));
  const double seed_s = seeding_time.elapsed_s();
  results.write(bench::result_line("db")
                    .text("measure", "seed_accounts")
                    .integer("accounts", accounts)
                    .number("seconds", seed_s, 3)
                    .number("per_second", accounts / seed_s, 1)
                    .text("note", "Minimum-cost hashes"));

  // 2. Matches.
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<std::size_t> pick(0, ids.size() - 1);
  std::uniform_int_distribution<int> stat(0, 30);
  std::vector<double> write_us;
  write_us.reserve(static_cast<std::size_t>(matches));
  const bench::Stopwatch writing;
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
    const bench::Stopwatch write;
    must(matches_rules.record_match(match), "record_match");
    write_us.push_back(write.elapsed_us());
  }
  const double match_s = writing.elapsed_s();
  const stats::Summary writes = stats::summarize(write_us);
  results.write(bench::result_line("db")
                    .text("measure", "match_writes")
                    .integer("matches", matches)
                    .integer("players", players)
                    .number("per_second", matches / match_s, 1)
                    .number("p50_us", writes.p50, 1)
                    .number("p99_us", writes.p99, 1));

  // 3. Logins at the production cost.
  db::Accounts live(*store, db::AccountsOptions{});
  must(live.register_account("bench_user", "correct horse battery", "", kT0), "register");
  std::vector<std::string> tokens;
  std::vector<double> login_ms;
  const bench::Stopwatch logging_in;
  for (int i = 0; i < logins; ++i) {
    const bench::Stopwatch login;
    tokens.push_back(
        must(live.login("bench_user", "correct horse battery", "", kT0 + i), "login").token);
    login_ms.push_back(login.elapsed_ms());
  }
  const double logins_per_s = logins / logging_in.elapsed_s();
  const stats::Summary login_times = stats::summarize(login_ms);
  results.write(bench::result_line("db")
                    .text("measure", "logins")
                    .text("cost", "argon2id_interactive")
                    .integer("logins", logins)
                    .number("per_second", logins_per_s, 2)
                    .number("p50_ms", login_times.p50, 2)
                    .number("p99_ms", login_times.p99, 2));

  // 4. Token checks.
  std::vector<double> check_us;
  check_us.reserve(static_cast<std::size_t>(token_checks));
  const bench::Stopwatch checking;
  for (int i = 0; i < token_checks; ++i) {
    const bench::Stopwatch check;
    must(live.check_session(tokens[static_cast<std::size_t>(i) % tokens.size()], kT0 + 1000),
         "check_session");
    check_us.push_back(check.elapsed_us());
  }
  const double checks_per_s = token_checks / checking.elapsed_s();
  const stats::Summary checks = stats::summarize(check_us);
  results.write(bench::result_line("db")
                    .text("measure", "token_checks")
                    .integer("checks", token_checks)
                    .number("per_second", checks_per_s, 1)
                    .number("p50_us", checks.p50, 1)
                    .number("p99_us", checks.p99, 1));

  // 5. Leaderboards.
  double worst_p99_us = 0;
  for (const db::LeaderboardKind kind :
       {db::LeaderboardKind::Rating, db::LeaderboardKind::Kills, db::LeaderboardKind::WinRate}) {
    for (const int limit : {10, 100}) {
      std::vector<double> query_us;
      for (int q = 0; q < queries; ++q) {
        const bench::Stopwatch query;
        const auto board = must(matches_rules.leaderboard(kind, limit), "leaderboard");
        query_us.push_back(query.elapsed_us());
        if (board.empty()) {
          std::fprintf(stderr, "db-bench: empty %s board\n", board_name(kind));
          return 1;
        }
      }
      const stats::Summary top = stats::summarize(query_us);
      worst_p99_us = std::max(worst_p99_us, top.p99);
      results.write(bench::result_line("db")
                        .text("measure", "leaderboard_top")
                        .text("board", board_name(kind))
                        .integer("limit", limit)
                        .integer("accounts", accounts)
                        .number("p50_us", top.p50, 1)
                        .number("p99_us", top.p99, 1));
    }
    std::vector<double> rank_us;
    for (int q = 0; q < queries; ++q) {
      const db::AccountId id = ids[pick(rng)];
      const bench::Stopwatch query;
      (void)must(matches_rules.rank_of(id, kind), "rank_of");
      rank_us.push_back(query.elapsed_us());
    }
    const stats::Summary rank = stats::summarize(rank_us);
    worst_p99_us = std::max(worst_p99_us, rank.p99);
    results.write(bench::result_line("db")
                      .text("measure", "rank_of")
                      .text("board", board_name(kind))
                      .integer("accounts", accounts)
                      .number("p50_us", rank.p50, 1)
                      .number("p99_us", rank.p99, 1));
  }
  results.write(bench::result_line("db")
                    .flag("summary", true)
                    .integer("accounts", accounts)
                    .number("logins_per_s", logins_per_s, 2)
                    .number("token_checks_per_s", checks_per_s, 1)
                    .number("match_writes_per_s", matches / match_s, 1)
                    .number("leaderboard_worst_p99_us", worst_p99_us, 1));
  store.reset();
  if (remove_dir) std::filesystem::remove_all(dir);
  return 0;
}
