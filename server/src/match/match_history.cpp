/// A match's entity states by tick and the read-out of the world after each step
/// (match_history.h).

#include "match_history.h"

#include <cassert>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/movement.h"

namespace ricochet::server {

namespace {

std::array<float, 3> to_array(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

std::span<const proto::EntityState> History::states_at(std::uint32_t tick) const {
  const HistoryEntry& entry = ring[tick % ring.size()];
  if (tick == 0 || entry.tick != tick) return {};
  return entry.states;
}

void record_history(std::uint32_t tick, const physics::World& world, Roster& roster, Combat& combat,
                    History& history) {
  // Read every live body in one call: the players', then the grenades'.
  history.body_ids.clear();
  for (const Player& player : roster.players) {
    if (player.alive) history.body_ids.push_back(player.body);
  }
  for (const Projectile& shot : combat.projectiles) {
    if (!shot.grenade.is_null()) history.body_ids.push_back(shot.grenade);
  }
  history.positions.resize(history.body_ids.size());
  history.velocities.resize(history.body_ids.size());
  physics::BodyReadout readout;
  readout.positions = history.positions;
  readout.linear_velocities = history.velocities;
  [[maybe_unused]] const physics::Status read = world.read_bodies(history.body_ids, readout);
  assert(read.ok());  // every listed body is live
  std::size_t next = 0;
  for (Player& player : roster.players) {
    if (!player.alive) continue;
    player.position_m = history.positions[next];
    player.velocity_mps = history.velocities[next];
    ++next;
  }
  for (Projectile& shot : combat.projectiles) {
    if (!shot.grenade.is_null()) {
      shot.position_m = history.positions[next];
      shot.velocity_mps = history.velocities[next];
      ++next;
    } else if (const auto state = world.projectile_state(shot.rocket); state.ok()) {
      shot.position_m = state.value().position;
      shot.velocity_mps = state.value().velocity;
    }
  }

  combat.lag_samples.clear();
  const physics::Real radius = player_body_def(physics::Vec3::Zero()).radius;
  for (const Player& player : roster.players) {
    combat.lag_samples.push_back(LagSample{player.entity_id, player.body, player.position_m,
                                           static_cast<float>(radius), player.life, player.alive});
  }
  combat.lag.record(tick, combat.lag_samples);

  // Players and projectiles, merged by id (both lists are sorted by it).
  HistoryEntry& entry = history.ring[tick % history.ring.size()];
  entry.tick = tick;
  entry.states.clear();
  std::size_t p = 0, q = 0;
  while (p < roster.players.size() || q < combat.projectiles.size()) {
    proto::EntityState state;
    if (q == combat.projectiles.size() ||
        (p < roster.players.size() &&
         roster.players[p].entity_id < combat.projectiles[q].entity_id)) {
      const Player& player = roster.players[p++];
      state.id = player.entity_id;
      state.position_m = to_array(player.position_m);
      state.velocity_mps = player.alive ? to_array(player.velocity_mps) : std::array<float, 3>{};
      state.flags = static_cast<std::uint8_t>(
          (player.grounded && player.alive ? proto::kEntityGrounded : 0) |
          (player.connected ? 0 : proto::kEntityDisconnected) |
          (player.alive ? 0 : proto::kEntityDead) |
          (player.alive && tick < player.protected_until ? proto::kEntityProtected : 0));
    } else {
      const Projectile& shot = combat.projectiles[q++];
      state.id = shot.entity_id;
      state.position_m = to_array(shot.position_m);
      state.velocity_mps = to_array(shot.velocity_mps);
      state.flags =
          proto::kind_flags(shot.weapon == WeaponKind::GrenadeLauncher ? proto::EntityKind::Grenade
                                                                       : proto::EntityKind::Rocket);
    }
    state.orientation_xyzw = {0, 0, 0, 1};  // players never spin; projectiles are round
    entry.states.push_back(state);
  }
}

}  // namespace ricochet::server
