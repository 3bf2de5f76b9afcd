#pragma once
/// A recorded match opened for playback: the map and config a recording carries, a Match built
/// from them (recording off), and that Match as the ReplaySimulation replay.h drives. Used by
/// ricochet-replay and match-bench.

#include <string>
#include <variant>

#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "ricochet/server/recording.h"
#include "ricochet/server/replay.h"

namespace ricochet::server {

/// Match as a ReplaySimulation.
class MatchSimulation final : public ReplaySimulation {
 public:
  explicit MatchSimulation(Match& match) : match_(match) {}
  void apply(const RecordedEvent& event) override { match_.apply(event); }
  void step(std::span<const RecordedInput> inputs) override { match_.step_recorded(inputs); }
  std::uint64_t state_hash() const override { return match_.state_hash(); }

 private:
  Match& match_;
};

/// Builds the recorded match: its map from the recorded files (parse_map_files), its config
/// from the recorded codec (decode_match_config), recording off. Fails naming what was refused:
/// "its map: ...", "its config: ...", "its match: ...".
std::variant<Match, std::string> open_recorded_match(const Recording& recording);

}  // namespace ricochet::server
