#pragma once
/// The rules of a match: its mode, its lifecycle and what ends it, and the score a player takes
/// away from it.
///
///   waiting ──(min_players connected)──▶ warmup ──(warmup_s)──▶ running ──(limit)──▶ ended
///      ▲                                   │
///      └──────(fewer than min_players)─────┘
///
/// In waiting and warmup everyone plays (damage, deaths and respawns work) but nothing counts.
/// Entering running resets every score, respawns everyone and resets the pickups; from then on
/// kills count and the frag and time limits apply. A match ends at its limit, or when the server
/// stops (end()).
///
/// Scoring: a kill gives the killer +1; dying by one's own hand or the world (a kill volume, the
/// map's bounds) gives -1. In team deathmatch a kill also gives the killer's team +1, a team kill
/// gives that team -1 (and the killer -1), and the frag limit is on the team score.

#include <cstdint>
#include <string>

#include "ricochet/server/map.h"

namespace ricochet::server {

enum class GameMode : std::uint8_t {
  FreeForAll,      ///< "ffa": every player for themselves
  TeamDeathmatch,  ///< "tdm": red against blue, teams balanced on join
};
/// "ffa" or "tdm".
const char* name(GameMode mode);

struct RulesConfig {
  GameMode mode = GameMode::FreeForAll;
  int min_players = 2;              ///< connected players that start the warmup, 1..64
  float warmup_s = 10;              ///< 0..600; 0 goes straight to running
  int frag_limit = 20;              ///< 0 (none)..1000; per player (ffa) or per team (tdm)
  float time_limit_s = 600;         ///< 0 (none)..86400, of running
  float respawn_delay_s = 2;        ///< 0..60, from death to respawn
  float spawn_protection_s = 1.5f;  ///< 0..10: no damage taken after a spawn
  std::uint64_t seed = 1;           ///< the match's generator (weapon spread); any value

  std::string validate() const;
};

enum class MatchPhase : std::uint8_t { Waiting = 1, Warmup = 2, Running = 3, Ended = 4 };
const char* name(MatchPhase phase);

/// What one player did in the match (while running). Kept after the player leaves.
struct PlayerScore {
  std::uint64_t account = 0;
  std::string name;
  std::uint32_t entity_id = 0;  ///< the last entity it had
  Team team = Team::None;
  int kills = 0;
  int deaths = 0;
  int score = 0;
  int shots = 0;                   ///< rifle rays, rockets and grenades fired
  int hits = 0;                    ///< shots that hurt another player (an explosion counts once)
  int damage_dealt = 0;            ///< hit points taken from other players
  int damage_taken = 0;            ///< hit points lost, from anyone or the world
  std::uint32_t ticks_played = 0;  ///< running ticks it was connected for
};

}  // namespace ricochet::server
