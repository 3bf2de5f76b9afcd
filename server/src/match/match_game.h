#pragma once
/// The rules and combat of a match's step (match_rules.cpp, match_combat.cpp): phases, spawns,
/// weapons fired, projectiles, explosions, damage and deaths, hazards and pickups. These call
/// each other (a kill can end the match, the start of the match clears the projectiles), so they
/// share one context, Game, instead of a parameter list each.

#include <cstdint>

#include "mailbox.h"
#include "match_checks.h"
#include "match_combat.h"
#include "match_live.h"
#include "match_rules.h"
#include "ricochet/physics/world.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "ricochet/server/match_config.h"
#include "roster.h"

namespace ricochet::server {

/// What the rules and combat work on. They read the config, the map, the tick and the players'
/// connection part (connected, applied input, latency); they change the world (bodies,
/// projectiles, impulses), the players' game part and scores, the roster's entity ids (each
/// projectile takes one), the rules' state (phase, team scores, generator, pickups) and the
/// projectiles; they tell the clients through the mailbox and count in `counters` (violations
/// through `violations`). They never change the history, the snapshots or the recording; they
/// note deaths in `live_kills` for the live feed, which is not game state.
struct Game {
  const MatchConfig& config;
  const Map& map;
  const std::uint32_t& tick;  ///< the match's steps run: step_physics counts on
  physics::World& world;
  Roster& roster;
  RulesState& rules;
  Combat& combat;
  Mailbox& mailbox;
  MatchCounters& counters;
  ViolationReport violations;
  /// Where deaths are noted for the live feed: null while nobody watches.
  LiveKills* live_kills;

  /// `seconds` in whole ticks of this match, rounded.
  std::uint32_t ticks_of(float seconds) const;
  /// Queues `event` to every connected player.
  void broadcast(const wire::GameEvent& event) { mailbox.broadcast(roster, event); }
};

// --- the rules (match_rules.cpp) ---
/// The team a newcomer joins: the smaller, then the weaker (team deathmatch); None otherwise.
Team balanced_team(const Game& game);
/// Puts a player (back) into play at a spawn: a new body, full health, the start weapons.
void spawn(Game& game, Player& player);
/// The phase step: waiting → warmup → running → ended by player count and ticks, the running
/// ticks played, the respawns due.
void update_rules(Game& game);
void enter_phase(Game& game, MatchPhase phase);
/// Ends the match for `reason`, telling everyone.
void finish(Game& game, wire::MatchEndReason reason);
/// The phase, its ticks, the scores: what a client needs to show the match (a MatchState).
wire::GameEvent match_state_event(const Game& game);
/// Tells a newcomer the state of the match: the phase and the pickups that are down.
void queue_arrival(Game& game, std::uint64_t account);

// --- combat (match_combat.cpp) ---
/// Weapon switches and shots from each player's applied input: rifle rays (lag compensated),
/// rockets and grenades launched.
void fire_weapons(Game& game);
/// Rockets that hit something and fuses that ran out explode (after the physics step).
void resolve_projectiles(Game& game);
/// Kill volumes and the map's bounds.
void apply_hazards(Game& game);
/// Pickups that come back, and those the living players take.
void take_pickups(Game& game);
/// Removes every projectile in flight from the world.
void clear_projectiles(Game& game);
void reset_pickups(RulesState& rules);

}  // namespace ricochet::server
