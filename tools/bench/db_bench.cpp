/// db-bench: what the database costs, on a real SQLite file in a temporary directory and/or a
/// real PostgreSQL database (--postgres-url, or a throwaway cluster it starts itself the way the
/// tests do: tests/testing/postgres_cluster.h, fsync off). Each backend gets the same run:
///
///   1. seeds --accounts accounts (Minimum-cost hashes: seeding is not what is measured)
///   2. records --matches matches of --players players each (match writes/s: one transaction
///      per match with results, stats and Elo updates); with --writers N > 1, again from N
///      processes at once, each with its own connection (several servers on one database)
///   3. logs in --logins times at Argon2id interactive cost (logins/s: dominated by Argon2id)
///   4. checks --token-checks session tokens (token checks/s: one SHA-256 and one indexed read)
///   5. leaderboard latency p50/p99: top 10 and top 100 per board, and a random account's rank
///
/// Prints one JSON line per measurement and a summary line per backend (each with "backend").
/// Percentiles are nearest rank (ricochet/stats/percentile.h).
///
///   db-bench [--backend sqlite|postgres|both] [--postgres-url URL] [--writers 1]
///            [--accounts 100000] [--matches 20000] [--players 10] [--logins 20]
///            [--token-checks 20000] [--queries 2000] [--dir DIR] [--out FILE]

#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "harness.h"
#include "postgres_cluster.h"
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

/// What one backend's run is given.
struct Run {
  std::string backend;      ///< "sqlite" or "postgres", in every result line
  std::string url_or_path;  ///< db::open_store's
  int accounts, matches, players, logins, token_checks, queries, writers;
};

/// Match `m` of `players` distinct random accounts with random stats.
db::MatchRecord random_match(std::mt19937_64& rng, const std::vector<db::AccountId>& ids,
                             int players, int m) {
  std::uniform_int_distribution<std::size_t> pick(0, ids.size() - 1);
  std::uniform_int_distribution<int> stat(0, 30);
  db::MatchRecord match;
  match.uuid = db::new_match_uuid();
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
  return match;
}

/// A writer process's body: `count` matches through its own connection; 0 when all were written.
int write_matches(const std::string& url_or_path, const std::vector<db::AccountId>& ids,
                  int players, int count, int writer) {
  auto store = db::open_store({.url_or_path = url_or_path, .busy_timeout_ms = 60'000});
  if (!store.ok()) return 2;
  db::Matches rules(*store.value());
  std::mt19937_64 rng(1000 + static_cast<unsigned>(writer));
  for (int m = 0; m < count; ++m)
    if (!rules.record_match(random_match(rng, ids, players, m)).ok()) return 3;
  return 0;
}

/// Every measurement on one backend; 0 on success.
int bench_backend(const Run& cfg, bench::ResultsOut& results) {
  std::unique_ptr<db::Store> store = must(db::open_store({.url_or_path = cfg.url_or_path}), "open");
  db::AccountsOptions fast;
  fast.cost = db::PasswordCost::Minimum;
  db::Accounts seeding(*store, fast);
  db::MatchesOptions boards;
  boards.min_matches_for_win_rate = 3;
  db::Matches matches_rules(*store, boards);

  // 1. Accounts.
  std::vector<db::AccountId> ids;
  ids.reserve(static_cast<std::size_t>(cfg.accounts));
  bench::Stopwatch seeding_time;
  for (int i = 0; i < cfg.accounts; ++i)
    ids.push_back(
        must(seeding.register_account("player" + std::to_string(i), "correct horse", "", kT0),
             "register"));
  const double seed_s = seeding_time.elapsed_s();
  results.write(bench::result_line("db")
                    .text("backend", cfg.backend)
                    .text("measure", "seed_accounts")
                    .integer("accounts", cfg.accounts)
                    .number("seconds", seed_s, 3)
                    .number("per_second", cfg.accounts / seed_s, 1)
                    .text("note", "Minimum-cost hashes"));

  // 2. Matches.
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<std::size_t> pick(0, ids.size() - 1);
  std::vector<double> write_us;
  write_us.reserve(static_cast<std::size_t>(cfg.matches));
  const bench::Stopwatch writing;
  for (int m = 0; m < cfg.matches; ++m) {
    const db::MatchRecord match = random_match(rng, ids, cfg.players, m);
    const bench::Stopwatch write;
    must(matches_rules.record_match(match), "record_match");
    write_us.push_back(write.elapsed_us());
  }
  const double match_s = writing.elapsed_s();
  const stats::Summary writes = stats::summarize(write_us);
  results.write(bench::result_line("db")
                    .text("backend", cfg.backend)
                    .text("measure", "match_writes")
                    .integer("matches", cfg.matches)
                    .integer("players", cfg.players)
                    .number("per_second", cfg.matches / match_s, 1)
                    .number("p50_us", writes.p50, 1)
                    .number("p99_us", writes.p99, 1));

  // 2b. The same from several processes at once, each with its own connection.
  double parallel_per_s = 0;
  if (cfg.writers > 1) {
    const int each = std::max(1, cfg.matches / cfg.writers);
    const bench::Stopwatch parallel;
    std::vector<pid_t> writers;
    for (int w = 0; w < cfg.writers; ++w) {
      const pid_t pid = fork();
      if (pid < 0) {
        std::fprintf(stderr, "db-bench: fork failed\n");
        return 1;
      }
      if (pid == 0) _exit(write_matches(cfg.url_or_path, ids, cfg.players, each, w));
      writers.push_back(pid);
    }
    for (const pid_t pid : writers) {
      int status = 0;
      waitpid(pid, &status, 0);
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::fprintf(stderr, "db-bench: a writer process failed\n");
        return 1;
      }
    }
    parallel_per_s = each * cfg.writers / parallel.elapsed_s();
    results.write(bench::result_line("db")
                      .text("backend", cfg.backend)
                      .text("measure", "match_writes")
                      .integer("writers", cfg.writers)
                      .integer("matches", each * cfg.writers)
                      .integer("players", cfg.players)
                      .number("per_second", parallel_per_s, 1));
  }

  // 3. Logins at the production cost.
  db::Accounts live(*store, db::AccountsOptions{});
  must(live.register_account("bench_user", "correct horse battery", "", kT0), "register");
  std::vector<std::string> tokens;
  std::vector<double> login_ms;
  const bench::Stopwatch logging_in;
  for (int i = 0; i < cfg.logins; ++i) {
    const bench::Stopwatch login;
    tokens.push_back(
        must(live.login("bench_user", "correct horse battery", "", kT0 + i), "login").token);
    login_ms.push_back(login.elapsed_ms());
  }
  const double logins_per_s = cfg.logins / logging_in.elapsed_s();
  const stats::Summary login_times = stats::summarize(login_ms);
  results.write(bench::result_line("db")
                    .text("backend", cfg.backend)
                    .text("measure", "logins")
                    .text("cost", "argon2id_interactive")
                    .integer("logins", cfg.logins)
                    .number("per_second", logins_per_s, 2)
                    .number("p50_ms", login_times.p50, 2)
                    .number("p99_ms", login_times.p99, 2));

  // 4. Token checks.
  std::vector<double> check_us;
  check_us.reserve(static_cast<std::size_t>(cfg.token_checks));
  const bench::Stopwatch checking;
  for (int i = 0; i < cfg.token_checks; ++i) {
    const bench::Stopwatch check;
    must(live.check_session(tokens[static_cast<std::size_t>(i) % tokens.size()], kT0 + 1000),
         "check_session");
    check_us.push_back(check.elapsed_us());
  }
  const double checks_per_s = cfg.token_checks / checking.elapsed_s();
  const stats::Summary checks = stats::summarize(check_us);
  results.write(bench::result_line("db")
                    .text("backend", cfg.backend)
                    .text("measure", "token_checks")
                    .integer("checks", cfg.token_checks)
                    .number("per_second", checks_per_s, 1)
                    .number("p50_us", checks.p50, 1)
                    .number("p99_us", checks.p99, 1));

  // 5. Leaderboards.
  double worst_p99_us = 0;
  for (const db::LeaderboardKind kind :
       {db::LeaderboardKind::Rating, db::LeaderboardKind::Kills, db::LeaderboardKind::WinRate}) {
    for (const int limit : {10, 100}) {
      std::vector<double> query_us;
      for (int q = 0; q < cfg.queries; ++q) {
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
                        .text("backend", cfg.backend)
                        .text("measure", "leaderboard_top")
                        .text("board", board_name(kind))
                        .integer("limit", limit)
                        .integer("accounts", cfg.accounts)
                        .number("p50_us", top.p50, 1)
                        .number("p99_us", top.p99, 1));
    }
    std::vector<double> rank_us;
    for (int q = 0; q < cfg.queries; ++q) {
      const db::AccountId id = ids[pick(rng)];
      const bench::Stopwatch query;
      (void)must(matches_rules.rank_of(id, kind), "rank_of");
      rank_us.push_back(query.elapsed_us());
    }
    const stats::Summary rank = stats::summarize(rank_us);
    worst_p99_us = std::max(worst_p99_us, rank.p99);
    results.write(bench::result_line("db")
                      .text("backend", cfg.backend)
                      .text("measure", "rank_of")
                      .text("board", board_name(kind))
                      .integer("accounts", cfg.accounts)
                      .number("p50_us", rank.p50, 1)
                      .number("p99_us", rank.p99, 1));
  }
  results.write(bench::result_line("db")
                    .text("backend", cfg.backend)
                    .flag("summary", true)
                    .integer("accounts", cfg.accounts)
                    .number("logins_per_s", logins_per_s, 2)
                    .number("token_checks_per_s", checks_per_s, 1)
                    .number("match_writes_per_s", cfg.matches / match_s, 1)
                    .integer("writers", cfg.writers)
                    .number("match_writes_per_s_writers", parallel_per_s, 1)
                    .number("leaderboard_worst_p99_us", worst_p99_us, 1));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "db-bench: logins, token checks, match writes and leaderboard latency on SQLite and "
      "PostgreSQL");
  int accounts = 100'000, matches = 20'000, players = 10, logins = 20, token_checks = 20'000,
      queries = 2'000, writers = 1;
  std::string backend = "sqlite", postgres_url, dir, out;
  app.add_option("--backend", backend, "sqlite, postgres or both (one after the other)")
      ->check(CLI::IsMember({"sqlite", "postgres", "both"}));
  app.add_option("--postgres-url", postgres_url,
                 "the PostgreSQL database to fill (default: a throwaway cluster, fsync off)");
  app.add_option("--writers", writers, "also write --matches matches from this many processes")
      ->check(CLI::Range(1, 64));
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
  int status = 0;
  Run run{"", "", accounts, matches, players, logins, token_checks, queries, writers};
  if (backend != "postgres") {
    run.backend = "sqlite";
    run.url_or_path = path;
    status = bench_backend(run, results);
  }
  if (status == 0 && backend != "sqlite") {
    run.backend = "postgres";
    run.url_or_path = postgres_url.empty()
                          ? ricochet::test::PostgresCluster::shared().create_database()
                          : postgres_url;
    status = bench_backend(run, results);
  }
  if (remove_dir) std::filesystem::remove_all(dir);
  return status;
}
