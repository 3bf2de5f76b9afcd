/// Opening a recorded match for playback (match_replay.h).

#include "ricochet/server/match_replay.h"

namespace ricochet::server {

std::variant<Match, std::string> open_recorded_match(const Recording& recording) {
  std::vector<MapFile> files;
  for (const RecordedFile& file : recording.header.map_files)
    files.push_back({file.path, file.text});
  MapResult map = parse_map_files(files);
  if (const auto* bad = std::get_if<MapError>(&map)) return "its map: " + bad->describe();
  auto config = decode_match_config(recording.header.config);
  if (const auto* bad = std::get_if<std::string>(&config)) return "its config: " + *bad;
  MatchConfig replay_config = std::get<MatchConfig>(config);
  replay_config.record = false;  // a replay records nothing itself
  auto created = Match::create(replay_config, std::get<Map>(map), 0);
  if (auto* bad = std::get_if<std::string>(&created)) return "its match: " + *bad;
  return std::move(std::get<Match>(created));
}

}  // namespace ricochet::server
