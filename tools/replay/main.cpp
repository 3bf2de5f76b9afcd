// ricochet-replay: re-simulates a recorded match from the recording alone, headless and as fast
// as it steps, checks every recorded hash and reports the first tick where they differ (or that
// all match) and the final scores.
//
//   ricochet-replay FILE [--json] [--export FILE.csv] [--keep-going]
//
// Exit codes: 0 every hash matched, 1 a hash differed, 2 the file is unreadable (or its map or
// config is refused), 3 the file was cut short (a crash: no footer) and every hash it holds
// matched up to where it stops, which is printed. Links the socket-free match library only.

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "ricochet/server/match_replay.h"
#include "ricochet/server/recording.h"
#include "ricochet/server/replay.h"
#include "ricochet/tools/json_text.h"

namespace {

using namespace ricochet::server;
using ricochet::tools::json_string;

/// The whole file, or nothing and `error` set.
std::optional<std::vector<std::uint8_t>> read_file(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    error = "cannot open";
    return std::nullopt;
  }
  const std::streamoff size = in.tellg();
  if (size < 0 || static_cast<std::uint64_t>(size) > kMaxRecordingBytes) {
    error = "a recording is at most ";
    error += std::to_string(kMaxRecordingBytes) + " bytes, got " + std::to_string(size);
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) {
    error = "read failed";
    return std::nullopt;
  }
  return bytes;
}

void print_text(const std::string& file, const Recording& recording, const ReplayReport& report,
                const std::vector<PlayerScore>& scores) {
  std::printf("%s: %llu steps (%.1f s of match) in %.3f s (%.0fx real time)\n", file.c_str(),
              static_cast<unsigned long long>(report.steps), report.simulated_s, report.wall_s,
              report.wall_s > 0 ? report.simulated_s / report.wall_s : 0.0);
  if (!report.complete) std::printf("the recording was cut short: %s\n", recording.cut.c_str());
  if (report.truncated) std::printf("the recording stopped early (it reached its size limit)\n");
  if (report.first_mismatch) {
    std::printf(
        "MISMATCH at tick %u: recorded hash %016llx, replayed %016llx (%zu of %zu hashes differ)\n",
        report.first_mismatch->tick,
        static_cast<unsigned long long>(report.first_mismatch->recorded),
        static_cast<unsigned long long>(report.first_mismatch->replayed), report.hashes_differing,
        report.hashes_checked);
  } else {
    std::printf("all %zu hashes match\n", report.hashes_checked);
  }
  std::printf("%-20s %6s %5s %6s %6s %6s %5s %7s %7s\n", "player", "team", "kills", "deaths",
              "score", "shots", "hits", "dealt", "taken");
  for (const PlayerScore& s : scores) {
    std::printf("%-20s %6d %5d %6d %6d %6d %5d %7d %7d\n", s.name.c_str(), static_cast<int>(s.team),
                s.kills, s.deaths, s.score, s.shots, s.hits, s.damage_dealt, s.damage_taken);
  }
}

void print_json(const std::string& file, const Recording& recording, const ReplayReport& report,
                const std::vector<PlayerScore>& scores) {
  std::string out = "{\"file\":" + json_string(file);
  out += ",\"steps\":" + std::to_string(report.steps);
  out += ",\"last_tick\":" + std::to_string(report.last_tick);
  out += ",\"simulated_s\":" + std::to_string(report.simulated_s);
  out += ",\"wall_s\":" + std::to_string(report.wall_s);
  out += ",\"complete\":";
  out += report.complete ? "true" : "false";
  out += ",\"cut\":";
  out += report.complete ? "null" : json_string(recording.cut);
  out += ",\"cut_offset\":";
  out += report.complete ? "null" : std::to_string(recording.cut_offset);
  out += ",\"truncated\":";
  out += report.truncated ? "true" : "false";
  out += ",\"hashes_checked\":" + std::to_string(report.hashes_checked);
  out += ",\"hashes_differing\":" + std::to_string(report.hashes_differing);
  out += ",\"first_mismatch_tick\":";
  out += report.first_mismatch ? std::to_string(report.first_mismatch->tick) : "null";
  out += ",\"scores\":[";
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const PlayerScore& s = scores[i];
    if (i) out += ',';
    out += "{\"account\":" + std::to_string(s.account);
    out += ",\"name\":" + json_string(s.name);
    out += ",\"entity\":" + std::to_string(s.entity_id);
    out += ",\"team\":" + std::to_string(static_cast<int>(s.team));
    out += ",\"kills\":" + std::to_string(s.kills);
    out += ",\"deaths\":" + std::to_string(s.deaths);
    out += ",\"score\":" + std::to_string(s.score);
    out += ",\"shots\":" + std::to_string(s.shots);
    out += ",\"hits\":" + std::to_string(s.hits);
    out += ",\"damage_dealt\":" + std::to_string(s.damage_dealt);
    out += ",\"damage_taken\":" + std::to_string(s.damage_taken) + "}";
  }
  out += "]}";
  std::printf("%s\n", out.c_str());
}

/// The exit codes above.
constexpr int kExitMatched = 0;
constexpr int kExitMismatch = 1;
constexpr int kExitUnreadable = 2;
constexpr int kExitCut = 3;

int fail(const std::string& file, const std::string& what) {
  std::fprintf(stderr, "ricochet-replay: %s: %s\n", file.c_str(), what.c_str());
  return kExitUnreadable;
}

}  // namespace

int main(int argc, char** argv) {
  std::string file;
  std::string export_path;
  bool json = false;
  bool keep_going = false;
  CLI::App app{"ricochet-replay: re-simulates a recorded match and checks its hashes"};
  app.add_option("FILE", file, "the recording")->required();
  app.add_flag("--json", json, "print the report as one JSON object");
  app.add_option("--export", export_path,
                 "write every step's player positions as CSV (tick,entity,x,y,z)");
  app.add_flag("--keep-going", keep_going, "replay to the end after a mismatch, counting them");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  const auto bytes = read_file(file, error);
  if (!bytes) return fail(file, error);
  auto read = read_recording(*bytes);
  if (const auto* bad = std::get_if<RecordingError>(&read)) {
    return fail(file, bad->message + " (byte " + std::to_string(bad->offset) + ")");
  }
  const Recording& recording = std::get<Recording>(read);

  auto opened = open_recorded_match(recording);
  if (const auto* bad = std::get_if<std::string>(&opened)) return fail(file, *bad);
  Match& match = std::get<Match>(opened);
  MatchSimulation simulation(match);

  std::FILE* csv = nullptr;
  if (!export_path.empty()) {
    csv = std::fopen(export_path.c_str(), "w");
    if (!csv) return fail(export_path, "cannot write");
    std::fprintf(csv, "tick,entity,x,y,z\n");
  }
  ReplayOptions options;
  options.stop_at_mismatch = !keep_going;
  options.wall_clock_s = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  if (csv) {
    options.after_step = [&](std::uint32_t tick) {
      for (const auto& state : match.entity_states()) {
        if ((state.flags & ricochet::proto::kEntityKindMask) != 0)
          continue;  // players only, not projectiles
        std::fprintf(csv, "%u,%u,%.9g,%.9g,%.9g\n", tick, state.id, state.position_m[0],
                     state.position_m[1], state.position_m[2]);
      }
    };
  }
  const ReplayReport report = replay(recording, simulation, options);
  if (csv && std::fclose(csv) != 0) return fail(export_path, "write failed");
  const std::vector<PlayerScore> scores = match.scoreboard();
  if (json) {
    print_json(file, recording, report, scores);
  } else {
    print_text(file, recording, report, scores);
  }
  if (report.first_mismatch) return kExitMismatch;
  return report.complete ? kExitMatched : kExitCut;
}
