// Chaos: the real ricochet-server binary killed with SIGKILL mid-match under bot load, run out of
// disk, and started on a read-only data directory. What must hold each time: the database passes
// PRAGMA integrity_check, every match that ended before the trouble is in it with its results,
// the errors are clear, and the bots (ricochet_bot, over real sockets on 127.0.0.1) sign in again
// with their session tokens and play on.
//
// The full and read-only disks are small tmpfs mounts, so these tests need root (CAP_SYS_ADMIN),
// as ./tools/test.sh has; run as another user they are skipped and say why. Every wait is
// bounded; the tests assert outcomes, never speeds.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ctest_budget.h"
#include "replay_process.h"
#include "ricochet/bot/bot.h"
#include "ricochet/bot/fleet.h"
#include "ricochet/db/store.h"
#include "run_until.h"
#include "server_process.h"

namespace ricochet::test::chaos_test {
namespace {

using namespace std::chrono_literals;
namespace asio = boost::asio;

constexpr std::chrono::seconds kStartBudget{10};
/// Bots register (Argon2), sign in, join, play a match of kTimeLimit and get their results.
constexpr std::chrono::seconds kTimeLimit{3};
constexpr std::chrono::seconds kMatchBudget{kTimeLimit + 17s};
/// From the server's return to every bot back in a match: their back-off is at most 4 s here.
constexpr std::chrono::seconds kReturnBudget{12};
constexpr int kShutdownGraceS = 5;
constexpr std::chrono::seconds kExitBudget{kShutdownGraceS + 3};
// The test's waits fit ctest's limit (ctest_budget.h), with no margin beyond them.
static_assert(fits_ctest(kStartBudget + kMatchBudget + 3s + 10s + kStartBudget + kReturnBudget +
                             kMatchBudget + kExitBudget,
                         0s));

std::string matches_toml(int players) {
  return "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
         "/server/maps/arena.toml\"]\nseed = 7\nwarmup_s = 0\nfrag_limit = 0\nrecord = true\n"
         "min_players = " +
         std::to_string(players) + "\ntime_limit_s = " + std::to_string(kTimeLimit.count()) + "\n";
}

bot::FleetConfig fleet_config(const ServerProcess& server, const std::string& name, int bots,
                              int matches) {
  bot::FleetConfig config;
  config.bot.host = "127.0.0.1";
  config.bot.control_port = server.control_port();
  config.bot.fingerprint = server.fingerprint();
  config.bot.name = name;
  config.bot.password = "password-of-" + name;
  config.bot.matches = matches;
  config.bot.max_reconnect_attempts = 10;
  config.bot.predict = false;
  config.bots = bots;
  return config;
}

bool every_bot(const bot::Fleet& fleet, auto holds) {
  for (const auto& each : fleet.bots()) {
    if (!holds(*each)) return false;
  }
  return true;
}

/// PRAGMA integrity_check on the file: "ok", or what SQLite found.
std::string integrity(const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    std::string error = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    return "cannot open: " + error;
  }
  std::string verdict;
  const auto collect = [](void* out, int, char** values, char**) {
    *static_cast<std::string*>(out) += values[0] ? values[0] : "(null)";
    return 0;
  };
  char* error = nullptr;
  if (sqlite3_exec(db, "PRAGMA integrity_check", collect, &verdict, &error) != SQLITE_OK) {
    verdict = std::string("integrity_check failed: ") + (error ? error : "");
    sqlite3_free(error);
  }
  sqlite3_close(db);
  return verdict;
}

/// Matches in the database, and each account's count of matches played.
struct Recorded {
  std::int64_t matches = -1;
  std::vector<int> per_bot;
};
Recorded recorded(const std::filesystem::path& path, const bot::Fleet& fleet) {
  Recorded out;
  auto store = db::open_sqlite_store({.path = path.string()});
  if (!store.ok()) return out;
  const auto matches = store.value()->match_count();
  if (matches.ok()) out.matches = matches.value();
  for (const auto& each : fleet.bots()) {
    const auto stats =
        store.value()->player_stats(static_cast<db::AccountId>(each->record().account_id));
    out.per_bot.push_back(stats.ok() ? stats.value().matches : -1);
  }
  return out;
}

/// A tmpfs of `megabytes` mounted at `path` for the test's lifetime.
class Tmpfs {
 public:
  Tmpfs(std::filesystem::path path, int megabytes) : path_(std::move(path)) {
    std::filesystem::create_directories(path_);
    const std::string options = "size=" + std::to_string(megabytes) + "m,mode=0700";
    if (mount("ricochet-chaos", path_.c_str(), "tmpfs", 0, options.c_str()) != 0) {
      error_ = std::string("mount tmpfs: ") + std::strerror(errno);
    }
  }
  ~Tmpfs() {
    if (error_.empty()) umount2(path_.c_str(), MNT_DETACH);
  }
  Tmpfs(const Tmpfs&) = delete;
  Tmpfs& operator=(const Tmpfs&) = delete;
  const std::string& error() const { return error_; }
  /// Remounts read-only (true) or read-write; empty, or what went wrong.
  std::string remount(bool read_only) const {
    const unsigned long flags = MS_REMOUNT | (read_only ? MS_RDONLY : 0);
    if (mount(nullptr, path_.c_str(), nullptr, flags, nullptr) != 0) return std::strerror(errno);
    return {};
  }

 private:
  std::filesystem::path path_;
  std::string error_;
};

/// Writes a file until the file system is full; its size.
std::uint64_t fill(const std::filesystem::path& file) {
  const int fd = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) return 0;
  const std::vector<char> block(1 << 16, 'x');
  std::uint64_t written = 0;
  for (;;) {
    const ssize_t n = write(fd, block.data(), block.size());
    if (n <= 0) break;
    written += static_cast<std::uint64_t>(n);
  }
  close(fd);
  return written;
}

#define SKIP_UNLESS_ROOT() \
  if (geteuid() != 0) GTEST_SKIP() << "mounts a tmpfs: needs root, as ./tools/test.sh runs"

TEST(Chaos, KillNineMidMatchLosesNoFinishedMatchAndBotsResumeTheirSessions) {
  ServerProcess server(matches_toml(4), kShutdownGraceS);
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  asio::io_context io;
  bot::Fleet fleet(io, fleet_config(server, "chaos", 4, 2));
  ASSERT_EQ(fleet.start(), "");

  // One whole match, then a little of the next, and kill -9.
  ASSERT_TRUE(run_until(
      io,
      [&] { return every_bot(fleet, [](const bot::Bot& b) { return b.metrics().matches == 1; }); },
      kMatchBudget))
      << fleet.report_json() << server.log();
  std::vector<std::uint64_t> snapshots_then;
  for (const auto& each : fleet.bots()) snapshots_then.push_back(each->metrics().snapshots);
  const auto in_next_match = [&] {  // a second of snapshots since the first results
    for (std::size_t i = 0; i < fleet.bots().size(); ++i) {
      if (fleet.bots()[i]->metrics().snapshots <= snapshots_then[i] + 60) return false;
    }
    return true;
  };
  ASSERT_TRUE(run_until(io, in_next_match, 3s)) << fleet.report_json() << server.log();
  server.kill_now();

  EXPECT_EQ(integrity(server.db_path()), "ok");
  const Recorded before = recorded(server.db_path(), fleet);
  EXPECT_EQ(before.matches, 1) << "the match that ended before the kill";
  EXPECT_EQ(before.per_bot, std::vector<int>(4, 1));

  // The same data directory and ports: the bots come back with their session tokens.
  server.restart();
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  // The interrupted match's recording was kept, and replays to its last whole chunk.
  std::vector<std::filesystem::path> interrupted;
  for (const auto& entry : std::filesystem::directory_iterator(server.data_dir() / "recordings")) {
    if (entry.path().string().ends_with(".interrupted.rcr")) interrupted.push_back(entry.path());
  }
  ASSERT_EQ(interrupted.size(), 1u) << server.log();
  const auto [code, output] = replay(interrupted.front());
  EXPECT_EQ(code, 3) << output;  // cut short, and every hash it holds matched
  EXPECT_NE(output.find("\"cut\""), std::string::npos) << output;
  ASSERT_TRUE(run_until(
      io, [&] { return fleet.done(); }, kReturnBudget + kMatchBudget))
      << fleet.report_json() << server.log();
  // After the restart a bot may play one match more than it was told (it can miss that its
  // first match there ended and join the next before the results come; see the stop note), so
  // the database is checked against what the bots played.
  const int played = fleet.bots().front()->metrics().matches;
  for (const auto& each : fleet.bots()) {
    const std::string& name = each->config().name;
    EXPECT_TRUE(each->record().error.empty()) << name << ": " << each->record().error;
    EXPECT_GE(each->metrics().matches, 2) << name;
    EXPECT_EQ(each->metrics().matches, played) << name;
    EXPECT_GE(each->metrics().resumes, 1) << name << " signed in again with its password";
  }
  server.terminate();
  EXPECT_EQ(server.wait_exit(kExitBudget), std::optional<int>(0)) << server.log();
  EXPECT_EQ(integrity(server.db_path()), "ok");
  const Recorded after = recorded(server.db_path(), fleet);
  EXPECT_EQ(after.matches, played) << "every match a bot got results of, and no other";
  EXPECT_EQ(after.per_bot, std::vector<int>(4, played));
}

TEST(Chaos, AFullDiskDelaysAMatchRecordWithAClearErrorButNotItsResultsAndLosesNothing) {
  SKIP_UNLESS_ROOT();
  TempDir dir("ricochet-chaos");
  const Tmpfs disk(dir.path() / "data", 32);
  ASSERT_EQ(disk.error(), "");
  ServerProcess server(matches_toml(2), kShutdownGraceS, "", dir.path() / "data");
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  asio::io_context io;
  bot::Fleet fleet(io, fleet_config(server, "full", 2, 1));
  ASSERT_EQ(fleet.start(), "");
  // Both bots in the match, then the disk fills up before it ends.
  ASSERT_TRUE(run_until(
      io,
      [&] {
        return every_bot(fleet, [](const bot::Bot& b) { return b.metrics().snapshots > 30; });
      },
      kMatchBudget))
      << fleet.report_json() << server.log();
  const std::filesystem::path filler = dir.path() / "data" / "filler";
  EXPECT_GT(fill(filler), 0u);

  ASSERT_TRUE(run_until(
      io, [&] { return server.log().find("its record could not be written") != std::string::npos; },
      kMatchBudget))
      << server.log();
  EXPECT_NE(server.log().find("full"), std::string::npos) << server.log();
  // Its players are not kept waiting: their results come at once, the record pending.
  ASSERT_TRUE(run_until(
      io, [&] { return fleet.done(); }, kMatchBudget))
      << fleet.report_json() << server.log();
  for (const auto& each : fleet.bots()) {
    EXPECT_TRUE(each->record().error.empty()) << each->record().error;
    ASSERT_EQ(each->record().results.size(), 1u);
    EXPECT_TRUE(each->record().results[0].record_pending());
  }

  // Space again: the kept record is written.
  std::filesystem::remove(filler);
  ASSERT_TRUE(run_until(
      io,
      [&] { return server.log().find("its record was written at attempt") != std::string::npos; },
      kReturnBudget + kMatchBudget))
      << server.log();
  server.terminate();
  EXPECT_EQ(server.wait_exit(kExitBudget), std::optional<int>(0)) << server.log();
  EXPECT_EQ(integrity(server.db_path()), "ok");
  const Recorded after = recorded(server.db_path(), fleet);
  EXPECT_EQ(after.matches, 1);
  EXPECT_EQ(after.per_bot, std::vector<int>(2, 1));
}

TEST(Chaos, AReadOnlyDataDirectoryIsRefusedAtStartWithAClearError) {
  SKIP_UNLESS_ROOT();
  TempDir dir("ricochet-chaos");
  const Tmpfs disk(dir.path() / "data", 16);
  ASSERT_EQ(disk.error(), "");
  ServerProcess server(matches_toml(2), kShutdownGraceS, "", dir.path() / "data");
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  server.terminate();
  ASSERT_EQ(server.wait_exit(kExitBudget), std::optional<int>(0)) << server.log();
  const std::string first_run = server.log();

  ASSERT_EQ(disk.remount(/*read_only=*/true), "");
  server.restart();
  const std::optional<int> code = server.wait_exit(kStartBudget);
  ASSERT_TRUE(code.has_value()) << "the server started on a read-only data directory";
  EXPECT_NE(*code, 0);
  const std::string second_run = server.log().substr(first_run.size());
  EXPECT_NE(second_run.find("read-only"), std::string::npos) << second_run;
  EXPECT_NE(second_run.find((dir.path() / "data").string()), std::string::npos) << second_run;

  ASSERT_EQ(disk.remount(/*read_only=*/false), "");
  EXPECT_EQ(integrity(server.db_path()), "ok");
}

}  // namespace
}  // namespace ricochet::test::chaos_test
