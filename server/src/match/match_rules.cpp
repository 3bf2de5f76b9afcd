/// The rules of a match (rules.h, match_game.h): the lifecycle, teams, spawns and respawns, the
/// limits.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "match_game.h"
#include "range_check.h"

namespace ricochet::server {

const char* name(GameMode mode) {
  return mode == GameMode::TeamDeathmatch ? "tdm" : "ffa";
}

const char* name(MatchPhase phase) {
  switch (phase) {
    case MatchPhase::Waiting:
      return "waiting";
    case MatchPhase::Warmup:
      return "warmup";
    case MatchPhase::Running:
      return "running";
    case MatchPhase::Ended:
      return "ended";
  }
  return "unknown";
}

std::string RulesConfig::validate() const {
  if (mode != GameMode::FreeForAll && mode != GameMode::TeamDeathmatch) {
    return "match rules mode must be ffa or tdm";
  }
  if (min_players < 1 || min_players > 64) {
    return range_error("match", "rules min_players", "1..64", static_cast<long long>(min_players));
  }
  if (!within(warmup_s, 0, 600)) return range_error("match", "rules warmup_s", "0..600", warmup_s);
  if (frag_limit < 0 || frag_limit > 1000) {
    return range_error("match", "rules frag_limit", "0..1000", static_cast<long long>(frag_limit));
  }
  if (!within(time_limit_s, 0, 86400)) {
    return range_error("match", "rules time_limit_s", "0..86400", time_limit_s);
  }
  if (!within(respawn_delay_s, 0, 60)) {
    return range_error("match", "rules respawn_delay_s", "0..60", respawn_delay_s);
  }
  if (!within(spawn_protection_s, 0, 10)) {
    return range_error("match", "rules spawn_protection_s", "0..10", spawn_protection_s);
  }
  return {};
}

std::uint32_t Game::ticks_of(float seconds) const {
  return static_cast<std::uint32_t>(std::lround(double(seconds) * config.tick.rate_hz));
}

Team balanced_team(const Game& game) {
  if (game.config.rules.mode != GameMode::TeamDeathmatch) return Team::None;
  int red = 0, blue = 0;
  for (const Player& player : game.roster.players) {
    red += player.team == Team::Red;
    blue += player.team == Team::Blue;
  }
  if (red != blue) return red < blue ? Team::Red : Team::Blue;
  const int red_score = game.rules.team_scores[static_cast<std::size_t>(Team::Red)];
  const int blue_score = game.rules.team_scores[static_cast<std::size_t>(Team::Blue)];
  return blue_score < red_score ? Team::Blue : Team::Red;  // the weaker team, red on a tie
}

namespace {

/// The spawn farthest from living enemies, among those of the player's team.
const MapSpawn& choose_spawn(const Game& game, const Player& player) {
  // In team deathmatch the spawns of the player's team when the map has any; otherwise, and
  // in free-for-all, every spawn (server/maps/FORMAT.md).
  const bool team_spawns =
      player.team != Team::None &&
      std::any_of(game.map.spawns.begin(), game.map.spawns.end(),
                  [&](const MapSpawn& spawn) { return spawn.team == player.team; });
  const auto usable = [&](const MapSpawn& spawn) {
    return !team_spawns || spawn.team == player.team;
  };
  const auto enemy = [&](const Player& other) {
    if (other.entity_id == player.entity_id || !other.alive) return false;
    return player.team == Team::None || other.team != player.team;
  };
  // Farthest from the nearest living enemy; among equals (no enemies yet) the one least
  // recently used, so that players joining an empty match spread out.
  const MapSpawn* best = nullptr;
  double best_distance = -1;
  const std::size_t count = game.map.spawns.size();
  for (std::size_t k = 0; k < count; ++k) {
    const MapSpawn& spawn = game.map.spawns[(k + player.entity_id) % count];
    if (!usable(spawn)) continue;
    double nearest = std::numeric_limits<double>::max();
    for (const Player& other : game.roster.players) {
      if (!enemy(other)) continue;
      nearest = std::min(nearest, double((other.position_m - spawn.position_m).squaredNorm()));
    }
    // Any player standing on the spawn makes it a poor choice (a stack of spheres).
    for (const Player& other : game.roster.players) {
      if (other.entity_id != player.entity_id && other.alive &&
          (other.position_m - spawn.position_m).norm() < 1.0) {
        nearest = std::min(nearest, 0.0);
      }
    }
    if (nearest > best_distance) {
      best_distance = nearest;
      best = &spawn;
    }
  }
  return best ? *best : game.map.spawns.front();  // create() checked there is a spawn
}

}  // namespace

void spawn(Game& game, Player& player) {
  const MapSpawn& at = choose_spawn(game, player);
  if (!player.body.is_null()) {
    [[maybe_unused]] const physics::Status destroyed = game.world.destroy_body(player.body);
    assert(destroyed.ok());
  }
  physics::BodyDef def = player_body_def(at.position_m);
  def.user_data = player.entity_id;  // what rockets and rays report
  const physics::Result<physics::BodyId> body = game.world.create_body(def);
  assert(body.ok());  // a valid definition in a world far below its body limit
  player.body = body.value();
  player.alive = true;
  ++player.life;
  player.position_m = at.position_m;
  player.velocity_mps = physics::Vec3::Zero();
  player.vitals = Vitals{};
  player.weapon = WeaponKind::Rifle;
  for (std::size_t k = 0; k < kWeaponCount; ++k) {
    player.ammo[k] = game.config.weapons.weapons[k].ammo_start;
  }
  player.next_fire_tick = game.tick;
  player.protected_until = game.tick + game.ticks_of(game.config.rules.spawn_protection_s);
  player.aim_yaw_rad = at.yaw_rad;
  player.aim_pitch_rad = 0;
  player.aimed = false;  // a spawn turns the view: the next aim is not a flick
  ++game.counters.respawns;
  wire::GameEvent event;
  wire::Spawned& spawned = *event.mutable_spawned();
  spawned.set_entity_id(player.entity_id);
  for (int axis = 0; axis < 3; ++axis) {
    spawned.add_position(static_cast<float>(at.position_m[axis]));
  }
  spawned.set_yaw(at.yaw_rad);
  spawned.set_protected_until_tick(player.protected_until);
  spawned.set_team(static_cast<wire::Team>(player.team));
  game.broadcast(event);
}

namespace {

void start_running(Game& game) {
  // What happened before the start does not count: fresh scores, everyone respawned, nothing
  // in flight, every pickup up.
  game.roster.departed.clear();
  game.rules.team_scores = {};
  clear_projectiles(game);
  reset_pickups(game.rules);
  for (Player& player : game.roster.players) {
    const PlayerScore fresh{
        player.account, player.name, player.entity_id, player.team, 0, 0, 0, 0, 0, 0, 0, 0};
    player.score = fresh;
  }
  enter_phase(game, MatchPhase::Running);
  for (Player& player : game.roster.players) spawn(game, player);
}

}  // namespace

void update_rules(Game& game) {
  const int connected = game.roster.connected_count();
  const bool enough = connected >= game.config.rules.min_players;
  switch (game.rules.phase) {
    case MatchPhase::Waiting:
      if (enough) {
        if (game.config.rules.warmup_s > 0) {
          enter_phase(game, MatchPhase::Warmup);
        } else {
          start_running(game);
        }
      }
      break;
    case MatchPhase::Warmup:
      if (!enough) {
        enter_phase(game, MatchPhase::Waiting);
      } else if (game.tick >= game.rules.phase_ends_tick) {
        start_running(game);
      }
      break;
    case MatchPhase::Running:
      if (game.rules.phase_ends_tick != 0 && game.tick >= game.rules.phase_ends_tick) {
        finish(game, wire::MATCH_END_REASON_TIME_LIMIT);
        return;
      }
      for (Player& player : game.roster.players) {
        if (player.connected) ++player.score.ticks_played;
      }
      break;
    case MatchPhase::Ended:
      return;
  }
  for (Player& player : game.roster.players) {
    if (!player.alive && game.tick >= player.respawn_tick) spawn(game, player);
  }
}

void enter_phase(Game& game, MatchPhase phase) {
  game.rules.phase = phase;
  game.rules.phase_started_tick = game.tick;
  game.rules.phase_ends_tick = 0;
  if (phase == MatchPhase::Warmup)
    game.rules.phase_ends_tick = game.tick + game.ticks_of(game.config.rules.warmup_s);
  if (phase == MatchPhase::Running && game.config.rules.time_limit_s > 0) {
    game.rules.phase_ends_tick = game.tick + game.ticks_of(game.config.rules.time_limit_s);
  }
  game.broadcast(match_state_event(game));
}

wire::GameEvent match_state_event(const Game& game) {
  wire::GameEvent event;
  wire::MatchState& state = *event.mutable_match_state();
  state.set_phase(static_cast<wire::MatchPhase>(game.rules.phase));
  state.set_phase_started_tick(game.rules.phase_started_tick);
  state.set_phase_ends_tick(game.rules.phase_ends_tick);
  state.set_frag_limit(game.config.rules.frag_limit);
  if (game.config.rules.mode == GameMode::TeamDeathmatch) {
    for (const Team team : {Team::Red, Team::Blue}) {
      wire::TeamScore& score = *state.add_team_scores();
      score.set_team(static_cast<wire::Team>(team));
      score.set_score(game.rules.team_scores[static_cast<std::size_t>(team)]);
    }
  }
  for (const Player& player : game.roster.players) {
    wire::PlayerScore& score = *state.add_scores();
    score.set_entity_id(player.entity_id);
    score.set_team(static_cast<wire::Team>(player.team));
    score.set_kills(player.score.kills);
    score.set_deaths(player.score.deaths);
    score.set_score(player.score.score);
  }
  return event;
}

void queue_arrival(Game& game, std::uint64_t account) {
  game.mailbox.queue(account, match_state_event(game));
  for (std::size_t k = 0; k < game.rules.pickups.size(); ++k) {
    const PickupState& pickup = game.rules.pickups[k];
    if (pickup.available) continue;
    wire::GameEvent event;
    wire::Pickup& down = *event.mutable_pickup();
    down.set_pickup_index(static_cast<std::uint32_t>(k));
    down.set_kind(static_cast<wire::PickupKind>(pickup.spot.kind));
    down.set_respawn_tick(pickup.respawn_tick);
    game.mailbox.queue(account, event);
  }
}

void finish(Game& game, wire::MatchEndReason reason) {
  game.rules.end_reason = reason;
  enter_phase(game, MatchPhase::Ended);
  wire::GameEvent event;
  event.mutable_match_ended()->set_reason(reason);
  game.broadcast(event);
}

}  // namespace ricochet::server
