// A recording survives a crash: the real ricochet-server binary records a match that bots play,
// is killed with SIGKILL in the middle of it, and the recording it was streaming to disk
// (`match-<id>-<started ms>.rcr.part`) replays with ricochet-replay to its last whole chunk,
// every hash in it matching, and says where it stops (exit 3). Every wait is bounded.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "ctest_budget.h"
#include "replay_process.h"
#include "ricochet/bot/fleet.h"
#include "server_process.h"

namespace ricochet::test::bot_recording_crash_test {
namespace {

using namespace std::chrono_literals;
namespace asio = boost::asio;

/// From the fork to the ports file, then the bots' sign-in (Argon2) and joining, then a tick
/// chunk (16 KiB: about 3 s of 8 players) reaching the file, then the replay and the margin.
constexpr std::chrono::seconds kStartBudget{10};
constexpr std::chrono::seconds kChunkBudget{30};
static_assert(fits_ctest(kStartBudget + kChunkBudget, std::chrono::seconds{10}));

/// The one `.rcr.part` in `directory` with at least `min_bytes`, or nothing.
std::optional<std::filesystem::path> part_file(const std::filesystem::path& directory,
                                               std::uintmax_t min_bytes) {
  std::error_code error;
  if (!std::filesystem::is_directory(directory, error)) return std::nullopt;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (name.ends_with(".rcr.part") && entry.file_size(error) >= min_bytes) return entry.path();
  }
  return std::nullopt;
}

long long json_number(const std::string& json, const std::string& key) {
  std::smatch match;
  if (!std::regex_search(json, match, std::regex("\"" + key + "\":(\\d+)"))) return -1;
  return std::stoll(match[1].str());
}

TEST(RecordingCrash, AKilledServersRecordingReplaysToItsLastWholeChunk) {
  ServerProcess server("count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
                       "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\n"
                       "record = true\nmin_players = 8\ntime_limit_s = 600\n");
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  asio::io_context io;
  bot::FleetConfig config;
  config.bot.host = "127.0.0.1";
  config.bot.control_port = server.control_port();
  config.bot.fingerprint = server.fingerprint();
  config.bot.name = "crash";
  config.bot.password = "password-of-crash";
  config.bot.skill = 0.9;
  config.bot.matches = 1;
  config.bots = 8;
  bot::Fleet fleet(io, config);
  ASSERT_EQ(fleet.start(), "");
  // The header (the arena's files) is small; past 24 KiB the file holds a whole tick chunk.
  const auto recordings = server.dir() / "data" / "recordings";
  std::optional<std::filesystem::path> part;
  const auto deadline = std::chrono::steady_clock::now() + kChunkBudget;
  while (!(part = part_file(recordings, 24 * 1024)) &&
         std::chrono::steady_clock::now() < deadline) {
    io.run_for(100ms);
    if (io.stopped()) io.restart();
  }
  ASSERT_TRUE(part) << "no recording in progress of 24 KiB in " << kChunkBudget.count() << " s\n"
                    << server.log();
  server.kill_now();
  ASSERT_EQ(server.wait_exit(5s), std::optional<int>(128 + SIGKILL));
  ASSERT_TRUE(std::filesystem::exists(*part)) << "the file in progress stays";

  const auto [status, output] = replay(*part);
  EXPECT_EQ(status, 3) << "cut short, every hash matching: " << output;
  EXPECT_NE(output.find("\"complete\":false"), std::string::npos) << output;
  EXPECT_NE(output.find("\"first_mismatch_tick\":null"), std::string::npos) << output;
  std::smatch cut;
  ASSERT_TRUE(
      std::regex_search(output, cut, std::regex(R"re("cut":"([^"]*replayable to tick (\d+))")re")))
      << output;
  const long long last_tick = std::stoll(cut[2].str());
  EXPECT_GT(last_tick, 60) << "more than a second of play";
  EXPECT_EQ(json_number(output, "last_tick"), last_tick) << output;
  EXPECT_GT(json_number(output, "hashes_checked"), 0) << output;
  // The readable part ends on a chunk boundary at or before the end of the file.
  const long long offset = json_number(output, "cut_offset");
  EXPECT_GT(offset, 0) << output;
  EXPECT_LE(offset, static_cast<long long>(std::filesystem::file_size(*part)));
  std::printf("[ figures  ] after SIGKILL: %s (%ju bytes) replays to tick %lld: %s\n",
              part->filename().c_str(), std::filesystem::file_size(*part), last_tick,
              cut[1].str().c_str());
}

}  // namespace
}  // namespace ricochet::test::bot_recording_crash_test
