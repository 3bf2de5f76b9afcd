// kill -9 while writing: a child process records 8-player matches as fast as it can and is
// killed with SIGKILL at different moments (after some tens of commits, with a small extra
// delay, with synchronous=FULL, and while it is still opening the file). After every kill the
// file must open cleanly, pass PRAGMA integrity_check, and hold only whole matches: each match
// has its 8 player rows, the lifetime stats add up to exactly the recorded matches, and the
// ratings are conserved and equal to each player's last rating_after.

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "db_test_util.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"
#include "sqlite_handle.h"

namespace ricochet::db::test::crash_test {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr int kPlayersPerMatch = 8;
constexpr int kAccounts = 24;

SqliteOptions options_for(const std::string& path, bool synchronous_full) {
  SqliteOptions options;
  options.path = path;
  options.synchronous_full = synchronous_full;
  return options;
}

/// The child: records random matches until killed. Never returns into the test framework.
[[noreturn]] void write_matches_until_killed(const SqliteOptions& options,
                                             const std::vector<AccountId>& accounts, pid_t parent) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive a test process that died
  if (getppid() != parent) _exit(5);
  auto store = open_sqlite_store(options);
  if (!store) _exit(2);
  Matches matches(*store.value());
  std::uint32_t seed = static_cast<std::uint32_t>(getpid());
  const auto next = [&seed](std::uint32_t n) {
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) % n;
  };
  const auto give_up = Clock::now() + 60s;  // a safety net; the parent kills it long before
  while (Clock::now() < give_up) {
    std::vector<AccountId> pool = accounts;
    MatchRecord match;
    match.uuid = new_match_uuid();
    match.map = "foundry";
    match.mode = "ffa";
    match.started_ms = 1000;
    match.ended_ms = 2000;
    for (int i = 0; i < kPlayersPerMatch; ++i) {
      std::swap(pool[static_cast<std::size_t>(i)],
                pool[static_cast<std::size_t>(i) + next(static_cast<std::uint32_t>(pool.size()) -
                                                        static_cast<std::uint32_t>(i))]);
      PlayerResult p;
      p.account = pool[static_cast<std::size_t>(i)];
      p.kills = static_cast<std::int32_t>(next(10));
      p.score = static_cast<std::int32_t>(next(20));
      p.damage_dealt = next(1000) / 4.0;
      p.seconds_played = 120;
      match.players.push_back(p);
    }
    if (!matches.record_match(match)) _exit(3);
  }
  _exit(4);
}

/// Kills and reaps the child when the test leaves early.
struct ChildProcess {
  pid_t pid = -1;
  ~ChildProcess() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
};

std::int64_t integer(sqlite3* db, const std::string& sql) {
  std::int64_t value = -1;
  EXPECT_EQ(sqlite::single_integer(db, sql, value), SQLITE_OK) << sql << ": " << sqlite3_errmsg(db);
  return value;
}

/// Every check on the reopened file; returns the number of matches in it.
std::int64_t check_whole_matches(const std::string& path) {
  auto store = must(open_sqlite_store(options_for(path, false)), "reopen after the kill");
  sqlite::Connection raw;
  EXPECT_EQ(sqlite::open(path, SQLITE_OPEN_READONLY, raw), SQLITE_OK);
  sqlite3* db = raw.get();
  std::string integrity;
  EXPECT_EQ(sqlite::single_text(db, "PRAGMA integrity_check", integrity), SQLITE_OK);
  EXPECT_EQ(integrity, "ok");

  const std::int64_t matches = integer(db, "SELECT COUNT(*) FROM matches");
  EXPECT_EQ(must(store->match_count(), "match_count"), matches);
  EXPECT_EQ(integer(db,
                    "SELECT COUNT(*) FROM matches AS m WHERE (SELECT COUNT(*) FROM match_players"
                    " AS p WHERE p.match_id = m.id) != " +
                        std::to_string(kPlayersPerMatch)),
            0)
      << "a match without its " << kPlayersPerMatch << " players";
  EXPECT_EQ(integer(db,
                    "SELECT COUNT(*) FROM match_players WHERE match_id NOT IN"
                    " (SELECT id FROM matches)"),
            0);
  EXPECT_EQ(integer(db, "SELECT COALESCE(SUM(matches), 0) FROM player_stats"),
            kPlayersPerMatch * matches);
  EXPECT_EQ(integer(db, "SELECT COALESCE(SUM(kills), 0) FROM player_stats"),
            integer(db, "SELECT COALESCE(SUM(kills), 0) FROM match_players"));
  EXPECT_GE(integer(db, "SELECT COALESCE(SUM(wins), 0) FROM player_stats"), matches);
  EXPECT_EQ(integer(db,
                    "SELECT COUNT(*) FROM player_stats AS s WHERE s.rating != (SELECT rating_after"
                    " FROM match_players WHERE account_id = s.account_id"
                    " ORDER BY match_id DESC LIMIT 1)"),
            0)
      << "a rating that is not the player's last rating_after";
  EXPECT_EQ(integer(db,
                    "SELECT ABS(COALESCE(SUM(rating), 0) - 1500.0 * COUNT(*)) < 1e-6"
                    " FROM player_stats"),
            1)
      << "Elo changes must sum to zero";
  return matches;
}

struct KillMoment {
  int new_matches;  ///< commits to wait for after the child starts
  std::chrono::microseconds extra_delay;
  bool synchronous_full;
};

TEST(CrashTest, KillDuringWritesLeavesOnlyWholeMatches) {
  TempDir dir;
  const std::string path = dir.file("crash.db");
  std::vector<AccountId> accounts;
  {
    auto store = must(open_sqlite_store(options_for(path, false)), "setup");
    for (int i = 0; i < kAccounts; ++i) {
      const std::string name = "player" + std::to_string(i);
      accounts.push_back(must(store->insert_account(name, name, "h", 0), "insert_account"));
    }
  }  // closed before fork: a connection must never cross a fork

  const KillMoment moments[] = {
      {50, 0us, false}, {30, 300us, false}, {30, 1100us, true}, {0, 2000us, false}};
  const auto test_deadline = Clock::now() + 20s;
  std::int64_t matches = 0;
  for (const KillMoment& moment : moments) {
    SCOPED_TRACE("kill after " + std::to_string(moment.new_matches) + " new matches + " +
                 std::to_string(moment.extra_delay.count()) + " us");
    const std::int64_t target = matches + moment.new_matches;
    const pid_t parent = getpid();
    ChildProcess child;
    child.pid = fork();
    ASSERT_GE(child.pid, 0) << "fork failed";
    if (child.pid == 0)
      write_matches_until_killed(options_for(path, moment.synchronous_full), accounts, parent);

    if (moment.new_matches > 0) {
      sqlite::Connection watcher;
      ASSERT_EQ(sqlite::open(path, SQLITE_OPEN_READONLY, watcher), SQLITE_OK);
      sqlite3_busy_timeout(watcher.get(), 100);
      for (std::int64_t seen = -1; seen < target;) {
        int status = 0;
        ASSERT_EQ(waitpid(child.pid, &status, WNOHANG), 0)
            << "the writer stopped by itself, exit code "
            << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        ASSERT_LT(Clock::now(), test_deadline)
            << "only " << seen << " of " << target << " matches committed in time";
        std::int64_t count = 0;
        if (sqlite::single_integer(watcher.get(), "SELECT COUNT(*) FROM matches", count) ==
            SQLITE_OK)
          seen = count;
        std::this_thread::sleep_for(200us);
      }
    }
    std::this_thread::sleep_for(moment.extra_delay);
    ASSERT_EQ(kill(child.pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(waitpid(child.pid, &status, 0), child.pid);
    child.pid = -1;
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        << "the writer ended before the kill, status " << status;

    const std::int64_t after = check_whole_matches(path);
    EXPECT_GE(after, target);
    matches = after;
  }
  EXPECT_GE(matches, 110);
}

}  // namespace
}  // namespace ricochet::db::test::crash_test
