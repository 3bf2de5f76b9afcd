/// Combat in a match (match.h): weapons fired, the lag-compensated rifle, rockets and grenades,
/// explosions, damage and deaths, kill volumes and pickups. Every rule here is deterministic:
/// entity order, the match's generator, integer hit points.

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/match.h"

namespace ricochet::server {

namespace {

/// How close a player's centre must come to a pickup's to take it, m.
constexpr physics::Real kPickupReach_m = 1.0;

}  // namespace

void Match::fire_weapons() {
  for (Player& shooter : players_) {
    const PlayerInput& input = shooter.applied;
    const std::uint32_t pressed = input.buttons & ~shooter.previous_buttons;
    shooter.previous_buttons = input.buttons;
    if (!shooter.alive || ended()) continue;
    if (const std::optional<WeaponKind> chosen = weapon_for_slot(input.weapon_slot)) {
      shooter.weapon = *chosen;
    }
    if (!input.pressed(proto::kButtonFire)) continue;
    const WeaponConfig& weapon = config_.weapons.weapons[static_cast<std::size_t>(shooter.weapon)];
    int& ammo = shooter.ammo[static_cast<std::size_t>(shooter.weapon)];
    if (tick_ < shooter.next_fire_tick || ammo <= 0) {
      // Holding the trigger is normal; pressing it again before the weapon is ready is a
      // refused shot (a client that fires faster than the weapon allows).
      if ((pressed & proto::kButtonFire) != 0 && ammo > 0) {
        note_violation(shooter, Violation::FireRate);
      }
      continue;
    }
    --ammo;
    shooter.next_fire_tick = tick_ + std::max<std::uint32_t>(1, ticks_of(weapon.fire_interval_s));
    ++counters_.shots_fired;
    if (counts()) ++shooter.score.shots;
    const physics::Vec3 eye = eye_position(shooter.position_m);
    const physics::Vec3 aim = aim_direction(shooter.aim_yaw_rad, shooter.aim_pitch_rad);
    if (shooter.weapon == WeaponKind::Rifle) {
      fire_rifle(shooter, eye, aim);
    } else {
      launch(shooter, shooter.weapon, eye, aim);
    }
  }
}

void Match::fire_rifle(Player& shooter, const physics::Vec3& eye, const physics::Vec3& aim) {
  const WeaponConfig& rifle = config_.weapons.weapons[static_cast<std::size_t>(WeaponKind::Rifle)];
  const physics::Vec3 direction =
      rifle.spread_rad > 0 ? spread_direction(aim, rifle.spread_rad, rng_) : aim;
  const ViewTime view =
      lag_.resolve(tick_, shooter.applied.view_tick, shooter.applied.view_fraction,
                   static_cast<double>(shooter.latency_us) / 1000.0);
  if (view.clamped) {
    ++counters_.view_claims_clamped;
    note_violation(shooter, Violation::ViewTick);
  }
  ++counters_.lag_compensated_shots;
  physics::RayHit hit;
  if (!lag_.cast(world_, eye, direction, rifle.range_m, view, shooter.entity_id, hit)) return;
  Player* victim = find_entity(static_cast<std::uint32_t>(hit.target.user_data));
  if (!victim || victim == &shooter) return;  // the map
  if (hurt(*victim, &shooter, WeaponKind::Rifle, rifle.damage) > 0 && counts()) {
    ++shooter.score.hits;
  }
}

void Match::launch(Player& shooter, WeaponKind weapon, const physics::Vec3& eye,
                   const physics::Vec3& aim) {
  const WeaponConfig& config = config_.weapons.weapons[static_cast<std::size_t>(weapon)];
  Projectile shot;
  shot.entity_id = next_entity_id_++;
  shot.weapon = weapon;
  shot.owner_entity = shooter.entity_id;
  shot.owner_team = shooter.team;
  shot.expires_tick = tick_ + std::max<std::uint32_t>(1, ticks_of(config.fuse_s));
  shot.position_m = eye;
  if (weapon == WeaponKind::RocketLauncher) {
    const auto rocket =
        world_.create_projectile(rocket_projectile(config, eye, aim, shooter.body, shot.entity_id));
    if (!rocket.ok()) return;  // the world refused it (its projectile limit): no shot
    shot.rocket = rocket.value();
    shot.velocity_mps = aim * config.projectile_speed_mps;
  } else {
    const std::optional<physics::Vec3> start =
        grenade_launch_origin(world_, eye, aim, shooter.body, config);
    if (!start) {  // no room in front of the shooter: it goes off in the hand
      projectiles_.push_back(shot);
      explode(projectiles_.back(), eye);
      projectiles_.pop_back();
      return;
    }
    const auto grenade =
        world_.create_body(grenade_body(config, *start, aim, shooter.velocity_mps, shot.entity_id));
    if (!grenade.ok()) return;
    shot.grenade = grenade.value();
    shot.position_m = *start;
  }
  projectiles_.push_back(shot);
}

void Match::resolve_projectiles() {
  // Rockets that touched something this step, in the world's (deterministic) order.
  for (const physics::ProjectileHitEvent& event : world_.projectile_hit_events()) {
    const auto at = std::find_if(
        projectiles_.begin(), projectiles_.end(),
        [&](const Projectile& p) { return p.entity_id == event.user_data && !p.rocket.is_null(); });
    if (at == projectiles_.end()) continue;
    const Projectile shot = *at;
    projectiles_.erase(at);
    explode(shot, explosion_center(event,
                                   config_.weapons.weapons[static_cast<std::size_t>(shot.weapon)]));
  }
  // Fuses that ran out (grenades) and rockets that flew too long or left the world.
  for (std::size_t k = 0; k < projectiles_.size();) {
    Projectile& shot = projectiles_[k];
    const bool rocket_gone = !shot.rocket.is_null() && !world_.is_valid(shot.rocket);
    if (!rocket_gone && tick_ < shot.expires_tick) {
      ++k;
      continue;
    }
    const Projectile done = shot;
    projectiles_.erase(projectiles_.begin() + static_cast<std::ptrdiff_t>(k));
    if (!done.grenade.is_null()) {
      const physics::Vec3 center = world_.body_state(done.grenade).value().position;
      [[maybe_unused]] const physics::Status destroyed = world_.destroy_body(done.grenade);
      assert(destroyed.ok());
      explode(done, center);
    } else if (!rocket_gone) {
      [[maybe_unused]] const physics::Status destroyed = world_.destroy_projectile(done.rocket);
      assert(destroyed.ok());
    }
  }
}

void Match::explode(const Projectile& shot, const physics::Vec3& center_m) {
  ++counters_.explosions;
  const WeaponConfig& weapon = config_.weapons.weapons[static_cast<std::size_t>(shot.weapon)];
  // Every body in range: the living players, and grenades still in flight (pushed only).
  explosion_targets_.clear();
  explosion_entities_.clear();
  const physics::Real player_radius = player_body_def(physics::Vec3::Zero()).radius;
  for (const Player& player : players_) {
    if (!player.alive) continue;
    explosion_targets_.push_back(
        ExplosionTarget{player.body, player.position_m, static_cast<float>(player_radius)});
    explosion_entities_.push_back(player.entity_id);
  }
  for (const Projectile& other : projectiles_) {
    if (other.grenade.is_null()) continue;
    const physics::BodyState state = world_.body_state(other.grenade).value();
    explosion_targets_.push_back(
        ExplosionTarget{other.grenade, state.position, static_cast<float>(state.radius)});
    explosion_entities_.push_back(0);
  }
  explosion_effects_.clear();  // explosion_effects appends
  explosion_effects(world_, center_m, weapon, explosion_targets_, explosion_effects_);
  Player* attacker = find_entity(shot.owner_entity);  // null when it left the match
  bool hit_someone = false;
  for (const ExplosionEffect& effect : explosion_effects_) {
    const ExplosionTarget& target = explosion_targets_[effect.target];
    [[maybe_unused]] const physics::Status pushed =
        world_.apply_impulse(target.body, effect.impulse_ns, target.center_m);
    assert(pushed.ok());
    Player* victim = find_entity(explosion_entities_[effect.target]);
    if (!victim || !victim->alive || effect.damage <= 0) continue;
    const int taken = hurt(*victim, attacker, shot.weapon, effect.damage);
    hit_someone |= taken > 0 && victim != attacker;
  }
  if (hit_someone && attacker && counts()) ++attacker->score.hits;
}

int Match::hurt(Player& victim, Player* attacker, WeaponKind weapon, int damage) {
  if (!victim.alive || ended() || tick_ < victim.protected_until) return 0;
  const bool teammate =
      attacker && attacker != &victim && victim.team != Team::None && attacker->team == victim.team;
  const int amount =
      scaled_damage(damage, damage_scale(config_.weapons, attacker == &victim, teammate));
  if (amount <= 0) return 0;
  const DamageResult result = apply_damage(victim.vitals, amount, config_.weapons.armor_absorb);
  const int taken = result.health_lost + result.armor_lost;
  ++counters_.hits;
  if (counts()) {
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
  if (victim.connected) queue_event(victim.account, event);
  if (attacker && attacker != &victim && attacker->connected) queue_event(attacker->account, event);
  if (result.killed) kill(victim, attacker, weapon, false);
  return taken;
}

void Match::kill(Player& victim, Player* attacker, WeaponKind weapon, bool from_world) {
  victim.alive = false;
  victim.vitals.health = 0;
  victim.respawn_tick = tick_ + std::max<std::uint32_t>(1, ticks_of(config_.rules.respawn_delay_s));
  if (!victim.body.is_null()) {
    [[maybe_unused]] const physics::Status destroyed = world_.destroy_body(victim.body);
    assert(destroyed.ok());
    victim.body = physics::BodyId{};
  }
  victim.velocity_mps = physics::Vec3::Zero();
  ++counters_.kills;
  if (counts()) {
    ++victim.score.deaths;
    // No attacker: the world (a penalty, as a suicide) or one who left the match (no one scores).
    const bool suicide = (!attacker && from_world) || attacker == &victim;
    const bool team_kill = attacker && attacker != &victim && victim.team != Team::None &&
                           attacker->team == victim.team;
    if (!attacker && !from_world) {
    } else if (suicide || team_kill) {
      Player& loser = suicide ? victim : *attacker;
      --loser.score.score;
      if (team_kill) --team_scores_[static_cast<std::size_t>(loser.team)];
    } else {
      ++attacker->score.kills;
      ++attacker->score.score;
      if (attacker->team != Team::None) ++team_scores_[static_cast<std::size_t>(attacker->team)];
    }
  }
  wire::GameEvent event;
  wire::Kill& died = *event.mutable_kill();
  died.set_killer_entity_id(attacker ? attacker->entity_id : 0);
  died.set_victim_entity_id(victim.entity_id);
  died.set_weapon(from_world ? wire::WEAPON_UNSPECIFIED : to_wire(weapon));
  died.set_tick(tick_);
  broadcast(event);
  // The frag limit: a player's score (ffa) or a team's (tdm).
  const int limit = config_.rules.frag_limit;
  if (!counts() || limit <= 0 || !attacker || attacker == &victim) return;
  const bool reached = config_.rules.mode == GameMode::TeamDeathmatch
                           ? team_scores_[static_cast<std::size_t>(attacker->team)] >= limit
                           : attacker->score.score >= limit;
  if (reached) finish(wire::MATCH_END_REASON_FRAG_LIMIT);
}

void Match::apply_hazards() {
  for (Player& player : players_) {
    if (!player.alive) continue;
    const bool in_volume = std::any_of(
        map_.kill_volumes.begin(), map_.kill_volumes.end(), [&](const MapKillVolume& volume) {
          return (player.position_m.array() >= volume.min_m.array()).all() &&
                 (player.position_m.array() <= volume.max_m.array()).all();
        });
    if (!in_volume && map_.contains(player.position_m)) continue;
    if (counts()) player.score.damage_taken += player.vitals.health;
    kill(player, nullptr, WeaponKind::Rifle, true);
  }
}

void Match::take_pickups() {
  for (std::size_t k = 0; k < pickups_.size(); ++k) {
    PickupState& pickup = pickups_[k];
    if (!pickup.available) {
      if (tick_ < pickup.respawn_tick) continue;
      pickup.available = true;
      wire::GameEvent event;
      wire::Pickup& back = *event.mutable_pickup();
      back.set_pickup_index(static_cast<std::uint32_t>(k));
      back.set_kind(static_cast<wire::PickupKind>(pickup.spot.kind));
      broadcast(event);
    }
    for (Player& player : players_) {
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
            const WeaponConfig& weapon = config_.weapons.weapons[w];
            used |= player.ammo[w] < weapon.ammo_max;
            player.ammo[w] =
                std::min(weapon.ammo_max, player.ammo[w] + weapon.ammo_per_pickup * amount);
          }
          break;
      }
      if (!used) continue;  // full: it stays for someone who needs it
      pickup.available = false;
      pickup.respawn_tick = tick_ + std::max<std::uint32_t>(1, ticks_of(pickup.spot.respawn_s));
      ++counters_.pickups_taken;
      wire::GameEvent event;
      wire::Pickup& taken = *event.mutable_pickup();
      taken.set_pickup_index(static_cast<std::uint32_t>(k));
      taken.set_kind(static_cast<wire::PickupKind>(pickup.spot.kind));
      taken.set_entity_id(player.entity_id);
      taken.set_amount(amount);
      taken.set_respawn_tick(pickup.respawn_tick);
      broadcast(event);
      break;
    }
  }
}

void Match::clear_projectiles() {
  for (const Projectile& shot : projectiles_) {
    if (!shot.grenade.is_null()) {
      [[maybe_unused]] const physics::Status destroyed = world_.destroy_body(shot.grenade);
      assert(destroyed.ok());
    } else if (world_.is_valid(shot.rocket)) {
      [[maybe_unused]] const physics::Status destroyed = world_.destroy_projectile(shot.rocket);
      assert(destroyed.ok());
    }
  }
  projectiles_.clear();
}

void Match::reset_pickups() {
  for (PickupState& pickup : pickups_) {
    pickup.available = true;
    pickup.respawn_tick = 0;
  }
}

}  // namespace ricochet::server
