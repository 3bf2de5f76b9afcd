// Writes the seed corpus of results_outbox_fuzz: outbox files of a free-for-all match of one
// player, a team deathmatch of four, an aborted match and one of 64 players,
// each checked to read back, in both modes of the target (first byte 0: as is, 1: header
// repaired) and once cut short. Run by `tools/fuzz.sh --seeds` from the repo root; the output is
// committed in tests/fuzz/corpus/results_outbox/.
//
//   results_outbox_seeds DIR

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "results_outbox_format.h"

namespace {

using namespace ricochet;
using namespace ricochet::server;

OutboxRecord record(const char* mode, int players, bool aborted) {
  OutboxRecord out;
  out.match_id = 7;
  db::MatchRecord& r = out.record;
  r.uuid = "0123456789abcdef0123456789abcdef";
  r.map = "arena";
  r.mode = mode;
  r.started_ms = 1'700'000'000'000;
  r.ended_ms = r.started_ms + 300'000;
  r.aborted = aborted;
  const bool teams = r.mode == db::kModeTeamDeathmatch;
  if (teams) r.team_scores = {12, 9};
  for (int i = 0; i < players; ++i) {
    db::PlayerResult p;
    p.account = 100 + i;
    p.team = teams ? (i % 2 == 0 ? db::kTeamRed : db::kTeamBlue) : db::kNoTeam;
    p.kills = i;
    p.deaths = 2;
    p.score = i - 1;
    p.shots = 40;
    p.hits = 11;
    p.damage_dealt = 330.5;
    p.damage_taken = 100;
    p.seconds_played = 299.75;
    r.players.push_back(p);
  }
  return out;
}

void write(const std::string& path, std::uint8_t mode, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.put(static_cast<char>(mode));
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "results_outbox_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: results_outbox_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const std::pair<const char*, OutboxRecord> seeds[] = {
      {"ffa_one", record("ffa", 1, false)},
      {"tdm_four", record("tdm", 4, false)},
      {"aborted", record("ffa", 3, true)},
      {"sixty_four", record("ffa", 64, false)},
  };
  for (const auto& [name, seed] : seeds) {
    const std::vector<std::uint8_t> bytes = encode_outbox_record(seed);
    if (!decode_outbox_record(bytes).ok) {
      std::fprintf(stderr, "results_outbox_seeds: %s does not read back\n", name);
      return 1;
    }
    write(dir + "/" + name + ".raw", 0, bytes);
    write(dir + "/" + name + ".repair", 1, bytes);
    write(dir + "/" + name + ".cut", 0,
          std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + bytes.size() / 2));
  }
  return 0;
}
