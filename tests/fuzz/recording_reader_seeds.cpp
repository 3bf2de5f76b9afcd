// Writes the seed corpus of recording_reader_fuzz: small recordings made by RecordingWriter (no
// ticks; players joining, moving, leaving; every event kind; hashes; a stopped writer), each
// checked to read back, in both modes of the target (first byte 0: as is, 1: checksums
// repaired) and once cut short. Run by `tools/fuzz.sh --seeds` from the repo root; the output is
// committed in tests/fuzz/corpus/recording_reader/.
//
//   recording_reader_seeds DIR

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/server/recording.h"

namespace {

using namespace ricochet::server;

RecordingHeader header(bool with_files) {
  RecordingHeader out;
  out.server_version = "seed";
  if (with_files) {
    out.map_files = {{"server/maps/arena.toml", "name = \"seed\"\n"}, {"ramps.obj", "v 0 0 0\n"}};
  }
  out.config = {8, 1, 16, 60};
  out.seed = 12345;
  out.hash_interval_ticks = 5;
  out.tick_rate_hz = 60;
  return out;
}

/// `players` players for `ticks` ticks, turning and moving; one leaves, one times out, the match
/// ends.
std::vector<std::uint8_t> match(int players, std::uint32_t ticks, std::size_t max_bytes) {
  RecordingWriter writer(header(players > 1), max_bytes);
  for (std::uint32_t tick = 1; tick <= ticks; ++tick) {
    writer.begin_tick(tick);
    const int present = tick > ticks / 2 ? players - 1 : players;
    for (int p = 0; p < players; ++p) {
      if (tick == 1 + static_cast<std::uint32_t>(p)) {
        writer.add_event({RecordedEventKind::Connect, 10u + p, "player" + std::to_string(p), 0});
      }
    }
    if (tick == ticks / 2 + 1 && players > 1) {
      writer.add_event({RecordedEventKind::Leave, 10u + players - 1, "", 0});
    }
    if (tick == ticks / 3 && players > 2)
      writer.add_event({RecordedEventKind::Disconnect, 11, "", 0});
    if (tick == ticks / 3 + 2 && players > 2)
      writer.add_event({RecordedEventKind::TimedOut, 11, "", 0});
    if (tick == ticks) writer.add_event({RecordedEventKind::End, 0, "", 3});
    for (int p = 0; p < present && p < static_cast<int>(tick); ++p) {
      RecordedInput input;
      input.entity_id = static_cast<std::uint32_t>(p + 1);
      input.input.sequence = tick - static_cast<std::uint32_t>(p);
      input.input.yaw_rad = std::sin(0.1f * static_cast<float>(tick + p));
      input.input.pitch_rad = tick % 3 == 0 ? 0.25f : 0.0f;
      input.input.move_forward = (tick / 7 + p) % 2 ? 1.0f : 0.0f;
      input.input.buttons =
          tick % 11 == 0 ? ricochet::proto::kButtonFire | ricochet::proto::kButtonJump : 0;
      input.input.weapon_slot = tick % 17 == 0 ? 2 : 0;
      input.input.view_tick = tick > 2 ? tick - 2 : 0;
      input.input.view_fraction = static_cast<std::uint8_t>(tick * 37);
      input.latency_us = 15'000 + 1'000 * (tick / 10);
      writer.add_input(input);
    }
    writer.end_tick();
    if (tick % 5 == 0) writer.add_hash(tick, 0x9E3779B97F4A7C15ull * tick);
  }
  return writer.finish();
}

void write(const std::string& path, std::uint8_t mode, const std::vector<std::uint8_t>& bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  const bool ok = file && std::fputc(mode, file) != EOF &&
                  std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  if (!file || std::fclose(file) != 0 || !ok) {
    std::fprintf(stderr, "recording_reader_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: recording_reader_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const std::pair<const char*, std::vector<std::uint8_t>> seeds[] = {
      {"empty", match(0, 0, 1 << 20)},
      {"one_player", match(1, 40, 1 << 20)},
      {"four_players", match(4, 120, 1 << 20)},
      {"stopped_at_limit", match(3, 400, 900)},
  };
  int count = 0;
  for (const auto& [name, bytes] : seeds) {
    if (!std::holds_alternative<Recording>(read_recording(bytes))) {
      std::fprintf(stderr, "recording_reader_seeds: seed %s does not read back\n", name);
      return 1;
    }
    write(dir + "/" + name + ".raw", 0, bytes);
    write(dir + "/" + name + ".repair", 1, bytes);
    count += 2;
  }
  std::vector<std::uint8_t> cut = seeds[2].second;
  cut.resize(cut.size() - 20);
  write(dir + "/four_players_cut.raw", 0, cut);
  std::printf("recording_reader_seeds: wrote %d seeds\n", count + 1);
  return 0;
}
