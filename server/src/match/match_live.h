#pragma once
/// A match's side of the live feed (live_frame.h): the feed it publishes to, when the next frame
/// is due, the deaths noted since the last one, and the phase that builds and publishes a frame
/// after the tick's steps. Nothing here is game state: it is neither hashed nor recorded, and
/// the game's phases only append to `kills`.

#include <cstdint>
#include <memory>
#include <vector>

#include "match_combat.h"
#include "match_rules.h"
#include "ricochet/proto/clock.h"
#include "ricochet/server/live_frame.h"
#include "ricochet/server/match_config.h"
#include "roster.h"

namespace ricochet::server {

/// The deaths since the last frame, noted by the combat while someone watches.
struct LiveKills {
  std::vector<LiveKill> kills;  ///< at most kMaxLiveKills
  std::uint32_t dropped = 0;    ///< beyond that

  void note(const LiveKill& kill);
};

struct LiveTap {
  std::shared_ptr<LiveFeed> feed;   ///< null: no feed attached
  proto::TimeUs next_frame_us = 0;  ///< server time the next frame is due at
  proto::TimeUs last_tick_us = 0;   ///< server time of the last tick that stepped; 0: none yet
  bool ended_shown = false;         ///< the frame of the ended phase went out: the last one
  LiveKills kills;

  /// Where the combat notes deaths: `kills` while someone watches, else nullptr.
  LiveKills* kill_log() { return feed && feed->watched() ? &kills : nullptr; }
};

/// After a tick's steps at server time `now` (µs), or once the match ended (by its rules or
/// Match::end()): when someone watches and a frame is due, copies what a frame shows from the
/// match's parts into a new frame and publishes it, with the deaths noted since the last one.
/// The first frame of the ended phase is due at once, whatever the rate, and is the last: a
/// viewer sees the match end rather than its last running frame. With nobody watching it only
/// forgets the deaths noted.
void publish_live_frame(proto::TimeUs now, const MatchConfig& config, std::uint32_t tick,
                        const Roster& roster, const Combat& combat, const RulesState& rules,
                        LiveTap& tap);

}  // namespace ricochet::server
