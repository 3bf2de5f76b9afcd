/// Combat in a match (match_game.h): weapons fired, the lag-compensated rifle, rockets and
/// grenades, explosions, damage and deaths, kill volumes and pickups. Every rule here is
/// deterministic: entity order, the match's generator, integer hit points.

#include <algorithm>
#include <cassert>
#include <cmath>

#include "match_game.h"
#include "ricochet/physics/scene_profile.h"

namespace ricochet::server {

namespace {

/// How close a player's centre must come to a pickup's to take it, m.
constexpr physics::Real kPickupReach_m = 1.0;

/// `from_world`: a kill volume or the map's bounds (no attacker, no weapon).
void kill(Game& game, Player& victim, Player* attacker, WeaponKind weapon, bool from_world) {
  victim.alive = false;
  victim.vitals.health = 0;
  victim.respawn_tick =
      game.tick + std::max<std::uint32_t>(1, game.ticks_of(game.config.rules.respawn_delay_s));
  if (!victim.body.is_null()) {
    [[maybe_unused]] const physics::Status destroyed = game.world.destroy_body(victim.body);
    assert(destroyed.ok());
    victim.body = physics::BodyId{};
  }
  victim.velocity_mps = physics::Vec3::Zero();
  ++game.counters.kills;
  if (game.rules.counts()) {
    ++victim.score.deaths;
    // No attacker: the world (a penalty, as a suicide) or one who left the match (no one scores).
    const bool suicide = (!attacker && from_world) || attacker == &victim;
    const bool team_kill = attacker && attacker != &victim && victim.team != Team::None &&
                           attacker->team == victim.team;
    if (!attacker && !from_world) {
    } else if (suicide || team_kill) {
      Player& loser = suicide ? victim : *attacker;
      --loser.score.score;
      if (team_kill) --game.rules.team_scores[static_cast<std::size_t>(loser.team)];
    } else {
      ++attacker->score.kills;
      ++attacker->score.score;
      if (attacker->team != Team::None)
        ++game.rules.team_scores[static_cast<std::size_t>(attacker->team)];
    }
  }
  wire::GameEvent event;
  wire::Kill& died = *event.mutable_kill();
  died.set_killer_entity_id(attacker ? attacker->entity_id : 0);
  died.set_victim_entity_id(victim.entity_id);
  died.set_weapon(from_world ? wire::WEAPON_UNSPECIFIED : to_wire(weapon));
  died.set_tick(game.tick);
  game.broadcast(event);
  if (game.live_kills) {
    game.live_kills->note(LiveKill{game.tick, attacker ? attacker->entity_id : 0u, victim.entity_id,
                                   from_world ? std::nullopt : std::optional<WeaponKind>(weapon)});
  }
  // The frag limit: a player's score (ffa) or a team's (tdm).
  const int limit = game.config.rules.frag_limit;
  if (!game.rules.counts() || limit <= 0 || !attacker || attacker == &victim) return;
  const bool reached =
      game.config.rules.mode == GameMode::TeamDeathmatch
          ? game.rules.team_scores[static_cast<std::size_t>(attacker->team)] >= limit
          : attacker->score.score >= limit;
  if (reached) finish(game, wire::MATCH_END_REASON_FRAG_LIMIT);
}

/// Damage from `attacker` (null: it left the match) with `weapon`, after spawn protection,
/// self damage and friendly fire. Returns the hit points taken.
int hurt(Game& game, Player& victim, Player* attacker, WeaponKind weapon, int damage) {
  if (!victim.alive || game.rules.ended() || game.tick < victim.protected_until) return 0;
  const bool teammate =
      attacker && attacker != &victim && victim.team != Team::None && attacker->team == victim.team;
  const int amount =
      scaled_damage(damage, damage_scale(game.config.weapons, attacker == &victim, teammate));
  if (amount <= 0) return 0;
  const DamageResult result = apply_damage(victim.vitals, amount, game.config.weapons.armor_absorb);
  const int taken = result.health_lost + result.armor_lost;
  ++game.counters.hits;
  if (game.rules.counts()) {
    victim.score.damage_taken += taken;
    if (attacker && attacker != &victim) attacker->score.damage_dealt += taken;
  }
  wire::GameEvent event;
  wire::Hit& hit = *event.mutable_hit();
  hit.set_attacker_entity_id(attacker ? attacker->entity_id : 0);
  hit.set_victim_entity_id(victim.entity_id);
  hit.set_weapon(to_wire(weapon));
  hit.set_damage(taken);
  hit.set_health_after(victim.vitals.health);
  hit.set_armor_after(victim.vitals.armor);
  if (victim.connected) game.mailbox.queue(victim.account, event);
  if (attacker && attacker != &victim && attacker->connected)
    game.mailbox.queue(attacker->account, event);
  if (result.killed) kill(game, victim, attacker, weapon, false);
  return taken;
}

void explode(Game& game, const Projectile& shot, const physics::Vec3& center_m) {
  ++game.counters.explosions;
  const WeaponConfig& weapon = game.config.weapons.weapons[static_cast<std::size_t>(shot.weapon)];
  // Every body in range: the living players, and grenades still in flight (pushed only).
  game.combat.explosion_targets.clear();
  game.combat.explosion_entities.clear();
  const physics::Real player_radius = player_body_def(physics::Vec3::Zero()).radius;
  for (const Player& player : game.roster.players) {
    if (!player.alive) continue;
    game.combat.explosion_targets.push_back(
        ExplosionTarget{player.body, player.position_m, static_cast<float>(player_radius)});
    game.combat.explosion_entities.push_back(player.entity_id);
  }
  for (const Projectile& other : game.combat.projectiles) {
    if (other.grenade.is_null()) continue;
    const physics::BodyState state = game.world.body_state(other.grenade).value();
    game.combat.explosion_targets.push_back(
        ExplosionTarget{other.grenade, state.position, static_cast<float>(state.radius)});
    game.combat.explosion_entities.push_back(0);
  }
  game.combat.explosion_effects.clear();  // explosion_effects appends
  explosion_effects(game.world, center_m, weapon, game.combat.explosion_targets,
                    game.combat.explosion_effects);
  Player* attacker = game.roster.find_entity(shot.owner_entity);  // null when it left the match
  const physics::Real cap_mps = game.config.quantization.max_speed_mps;
  bool hit_someone = false;
  for (const ExplosionEffect& effect : game.combat.explosion_effects) {
    const ExplosionTarget& target = game.combat.explosion_targets[effect.target];
    const physics::Vec3 before = game.world.body_state(target.body).value().linear_velocity;
    [[maybe_unused]] const physics::Status pushed =
        game.world.apply_impulse(target.body, effect.impulse_ns, target.center_m);
    assert(pushed.ok());
    const physics::Vec3 after = game.world.body_state(target.body).value().linear_velocity;
    const physics::Vec3 capped = capped_explosion_velocity(before, after, cap_mps);
    if (capped != after) {
      [[maybe_unused]] const physics::Status slowed =
          game.world.set_linear_velocity(target.body, capped);
      assert(slowed.ok());
    }
    Player* victim = game.roster.find_entity(game.combat.explosion_entities[effect.target]);
    if (!victim || !victim->alive || effect.damage <= 0) continue;
    const int taken = hurt(game, *victim, attacker, shot.weapon, effect.damage);
    hit_someone |= taken > 0 && victim != attacker;
  }
  if (hit_someone && attacker && game.rules.counts()) ++attacker->score.hits;
}

void fire_rifle(Game& game, Player& shooter, const physics::Vec3& eye, const physics::Vec3& aim) {
  const WeaponConfig& rifle =
      game.config.weapons.weapons[static_cast<std::size_t>(WeaponKind::Rifle)];
  const physics::Vec3 direction =
      rifle.spread_rad > 0 ? spread_direction(aim, rifle.spread_rad, game.rules.rng) : aim;
  const ViewTime view =
      game.combat.lag.resolve(game.tick, shooter.applied.view_tick, shooter.applied.view_fraction,
                              static_cast<double>(shooter.latency_us) / 1000.0);
  if (view.clamped) {
    ++game.counters.view_claims_clamped;
    note_violation(shooter, Violation::ViewTick, game.violations);
  }
  ++game.counters.lag_compensated_shots;
  physics::RayHit hit;
  if (!game.combat.lag.cast(game.world, eye, direction, rifle.range_m, view, shooter.entity_id,
                            hit)) {
    return;  // nothing hit
  }
  Player* victim = game.roster.find_entity(static_cast<std::uint32_t>(hit.target.user_data));
  if (!victim || victim == &shooter) return;  // the map
  if (hurt(game, *victim, &shooter, WeaponKind::Rifle, rifle.damage) > 0 && game.rules.counts()) {
    ++shooter.score.hits;
  }
}

void launch(Game& game, Player& shooter, WeaponKind weapon, const physics::Vec3& eye,
            const physics::Vec3& aim) {
  const WeaponConfig& config = game.config.weapons.weapons[static_cast<std::size_t>(weapon)];
  Projectile shot;
  shot.entity_id = game.roster.new_entity_id();
  shot.weapon = weapon;
  shot.owner_entity = shooter.entity_id;
  shot.owner_team = shooter.team;
  shot.expires_tick = game.tick + std::max<std::uint32_t>(1, game.ticks_of(config.fuse_s));
  shot.position_m = eye;
  if (weapon == WeaponKind::RocketLauncher) {
    const auto rocket = game.world.create_projectile(
        rocket_projectile(config, eye, aim, shooter.body, shot.entity_id));
    if (!rocket.ok()) return;  // the world refused it (its projectile limit): no shot
    shot.rocket = rocket.value();
    shot.velocity_mps = aim * config.projectile_speed_mps;
  } else {
    const std::optional<physics::Vec3> start =
        grenade_launch_origin(game.world, eye, aim, shooter.body, config);
    if (!start) {  // no room in front of the shooter: it goes off in the hand
      game.combat.projectiles.push_back(shot);
      explode(game, game.combat.projectiles.back(), eye);
      game.combat.projectiles.pop_back();
      return;
    }
    const auto grenade = game.world.create_body(
        grenade_body(config, *start, aim, shooter.velocity_mps, shot.entity_id));
    if (!grenade.ok()) return;
    shot.grenade = grenade.value();
    shot.position_m = *start;
  }
  game.combat.projectiles.push_back(shot);
}

}  // namespace

void fire_weapons(Game& game) {
  for (Player& shooter : game.roster.players) {
    const PlayerInput& input = shooter.applied;
    const std::uint32_t pressed = input.buttons & ~shooter.previous_buttons;
    shooter.previous_buttons = input.buttons;
    if (!shooter.alive || game.rules.ended()) continue;
    if (const std::optional<WeaponKind> chosen = weapon_for_slot(input.weapon_slot)) {
      shooter.weapon = *chosen;
    }
    if (!input.pressed(proto::kButtonFire)) continue;
    const WeaponConfig& weapon =
        game.config.weapons.weapons[static_cast<std::size_t>(shooter.weapon)];
    int& ammo = shooter.ammo[static_cast<std::size_t>(shooter.weapon)];
    if (game.tick < shooter.next_fire_tick || ammo <= 0) {
      // Holding the trigger is normal; pressing it again before the weapon is ready is a
      // refused shot (a client that fires faster than the weapon allows).
      if ((pressed & proto::kButtonFire) != 0 && ammo > 0) {
        note_violation(shooter, Violation::FireRate, game.violations);
      }
      continue;
    }
    --ammo;
    shooter.next_fire_tick =
        game.tick + std::max<std::uint32_t>(1, game.ticks_of(weapon.fire_interval_s));
    ++game.counters.shots_fired;
    if (game.rules.counts()) ++shooter.score.shots;
    const physics::Vec3 eye = eye_position(shooter.position_m);
    const physics::Vec3 aim = aim_direction(shooter.aim_yaw_rad, shooter.aim_pitch_rad);
    if (shooter.weapon == WeaponKind::Rifle) {
      fire_rifle(game, shooter, eye, aim);
    } else {
      launch(game, shooter, shooter.weapon, eye, aim);
    }
  }
}

void resolve_projectiles(Game& game) {
  // Rockets that touched something this step, in the world's (deterministic) order.
  for (const physics::ProjectileHitEvent& event : game.world.projectile_hit_events()) {
    const auto at = std::find_if(
        game.combat.projectiles.begin(), game.combat.projectiles.end(),
        [&](const Projectile& p) { return p.entity_id == event.user_data && !p.rocket.is_null(); });
    if (at == game.combat.projectiles.end()) continue;
    const Projectile shot = *at;
    game.combat.projectiles.erase(at);
    explode(game, shot,
            explosion_center(event,
                             game.config.weapons.weapons[static_cast<std::size_t>(shot.weapon)]));
  }
  // Fuses that ran out (grenades) and rockets that flew too long or left the world.
  for (std::size_t k = 0; k < game.combat.projectiles.size();) {
    Projectile& shot = game.combat.projectiles[k];
    const bool rocket_gone = !shot.rocket.is_null() && !game.world.is_valid(shot.rocket);
    if (!rocket_gone && game.tick < shot.expires_tick) {
      ++k;
      continue;
    }
    const Projectile done = shot;
    game.combat.projectiles.erase(game.combat.projectiles.begin() + static_cast<std::ptrdiff_t>(k));
    if (!done.grenade.is_null()) {
      const physics::Vec3 center = game.world.body_state(done.grenade).value().position;
      [[maybe_unused]] const physics::Status destroyed = game.world.destroy_body(done.grenade);
      assert(destroyed.ok());
      explode(game, done, center);
    } else if (!rocket_gone) {
      [[maybe_unused]] const physics::Status destroyed = game.world.destroy_projectile(done.rocket);
      assert(destroyed.ok());
    }
  }
}

void apply_hazards(Game& game) {
  for (Player& player : game.roster.players) {
    if (!player.alive) continue;
    const bool in_volume =
        std::any_of(game.map.kill_volumes.begin(), game.map.kill_volumes.end(),
                    [&](const MapKillVolume& volume) {
                      return (player.position_m.array() >= volume.min_m.array()).all() &&
                             (player.position_m.array() <= volume.max_m.array()).all();
                    });
    if (!in_volume && game.map.contains(player.position_m)) continue;
    if (game.rules.counts()) player.score.damage_taken += player.vitals.health;
    kill(game, player, nullptr, WeaponKind::Rifle, true);
  }
}

void take_pickups(Game& game) {
  for (std::size_t k = 0; k < game.rules.pickups.size(); ++k) {
    PickupState& pickup = game.rules.pickups[k];
    if (!pickup.available) {
      if (game.tick < pickup.respawn_tick) continue;
      pickup.available = true;
      wire::GameEvent event;
      wire::Pickup& back = *event.mutable_pickup();
      back.set_pickup_index(static_cast<std::uint32_t>(k));
      back.set_kind(static_cast<wire::PickupKind>(pickup.spot.kind));
      game.broadcast(event);
    }
    for (Player& player : game.roster.players) {
      if (!player.alive || (player.position_m - pickup.spot.position_m).norm() > kPickupReach_m) {
        continue;
      }
      const int amount = pickup.spot.amount;
      bool used = false;
      switch (pickup.spot.kind) {
        case PickupKind::Health:
          used = player.vitals.health < kMaxHealth;
          player.vitals.health = std::min(kMaxHealth, player.vitals.health + amount);
          break;
        case PickupKind::Armor:
          used = player.vitals.armor < kMaxArmor;
          player.vitals.armor = std::min(kMaxArmor, player.vitals.armor + amount);
          break;
        case PickupKind::Ammo:
          for (std::size_t w = 0; w < kWeaponCount; ++w) {
            const WeaponConfig& weapon = game.config.weapons.weapons[w];
            used |= player.ammo[w] < weapon.ammo_max;
            player.ammo[w] =
                std::min(weapon.ammo_max, player.ammo[w] + weapon.ammo_per_pickup * amount);
          }
          break;
      }
      if (!used) continue;  // full: it stays for someone who needs it
      pickup.available = false;
      pickup.respawn_tick =
          game.tick + std::max<std::uint32_t>(1, game.ticks_of(pickup.spot.respawn_s));
      ++game.counters.pickups_taken;
      wire::GameEvent event;
      wire::Pickup& taken = *event.mutable_pickup();
      taken.set_pickup_index(static_cast<std::uint32_t>(k));
      taken.set_kind(static_cast<wire::PickupKind>(pickup.spot.kind));
      taken.set_entity_id(player.entity_id);
      taken.set_amount(amount);
      taken.set_respawn_tick(pickup.respawn_tick);
      game.broadcast(event);
      break;
    }
  }
}

void clear_projectiles(Game& game) {
  for (const Projectile& shot : game.combat.projectiles) {
    if (!shot.grenade.is_null()) {
      [[maybe_unused]] const physics::Status destroyed = game.world.destroy_body(shot.grenade);
      assert(destroyed.ok());
    } else if (game.world.is_valid(shot.rocket)) {
      [[maybe_unused]] const physics::Status destroyed = game.world.destroy_projectile(shot.rocket);
      assert(destroyed.ok());
    }
  }
  game.combat.projectiles.clear();
}

void reset_pickups(RulesState& rules) {
  for (PickupState& pickup : rules.pickups) {
    pickup.available = true;
    pickup.respawn_tick = 0;
  }
}

}  // namespace ricochet::server
