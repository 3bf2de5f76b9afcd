#pragma once
/// Everything a Match holds (match.h keeps one pointer to it), by concern: each part's header
/// says what it holds and declares the phases that change it.
///   roster.h          the players and who left
///   mailbox.h         reliable events and the outbox
///   match_rules.h     phase, team scores, generator, pickups
///   match_combat.h    projectiles, lag compensation, explosion scratch
///   match_game.h      the rules and combat phases (over a Game context)
///   match_movement.h  inputs applied, movement, the physics step
///   match_checks.h    the input checks and violations
///   match_history.h   the entity states by tick
///   match_snapshots.h the snapshots and the send phase
///   match_recorder.h  the recording and the match hash
///   match_live.h      the live feed's frames (not game state)

#include <cstdint>

#include "mailbox.h"
#include "match_checks.h"
#include "match_combat.h"
#include "match_game.h"
#include "match_history.h"
#include "match_live.h"
#include "match_recorder.h"
#include "match_rules.h"
#include "match_snapshots.h"
#include "ricochet/physics/world.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "ricochet/server/match_config.h"
#include "ricochet/server/tick_clock.h"
#include "ricochet/server/tick_profile.h"
#include "ricochet/wire/game.pb.h"
#include "roster.h"

namespace ricochet::server {

struct MatchParts {
  /// `config` validated, with the map's bounds in its quantization; `world` holds the map.
  /// `now` starts the tick clock.
  MatchParts(const MatchConfig& config, const Map& map, physics::World world, proto::TimeUs now,
             ProfileClock profile_clock);

  MatchConfig config;
  Map map;
  physics::World world;
  TickClock clock;
  ProfileClock profile_clock;
  MatchLog log;
  std::uint32_t tick = 0;  ///< steps run
  Roster roster;
  RulesState rules;
  Combat combat;
  History history;
  Snapshots snapshots;
  Mailbox mailbox;
  Recorder recorder;
  LiveTap live;
  /// The payload receive() parses into, kept: parsing clears it but keeps its inputs'
  /// messages, so a payload allocates nothing.
  wire::ClientPayload incoming;
  TickProfile profile;
  MatchCounters counters;

  Game game() {
    return Game{config, map,     tick,     world,        roster,         rules,
                combat, mailbox, counters, violations(), live.kill_log()};
  }
  ViolationReport violations() { return ViolationReport{config.id, log, counters}; }
  std::uint64_t state_hash() const { return match_hash(world, tick, rules, roster, combat); }
};

}  // namespace ricochet::server
