#pragma once
/// Projectiles: swept spheres that never take part in contacts.
///
/// A shooter's bullets need three things from physics: a ballistic path, a hit test that never
/// tunnels, and a report of what was hit. A projectile gives exactly that and nothing else. Each
/// step it moves x += v·dt + ½·g·dt², v += g·dt (exact under constant gravity), sweeps that move
/// (the chord of the arc, g·dt²/8 off it: 0.5 mm at 60 Hz) against static shapes and against
/// bodies by their relative motion over the step, and at the first touch it stops: a
/// ProjectileHitEvent is recorded and the projectile is gone (its handle goes stale). It pushes
/// nothing; damage and knockback are game code (World::apply_impulse on the hit body).
///
/// It never enters the broadphase, the narrowphase or the solver, so a scene of players and
/// bullets pays for its bullets only in sweeps. Use a body with `fast = true` instead when the
/// bullet must bounce, roll or push.

#include <cstdint>

#include "ricochet/physics/body.h"
#include "ricochet/physics/events.h"
#include "ricochet/physics/types.h"

namespace ricochet::physics {

struct ProjectileDef {
  Vec3 position = Vec3::Zero();  ///< m, centre
  Vec3 velocity = Vec3::Zero();  ///< m/s, at most WorldDef::max_linear_speed
  Real radius = 0;               ///< m; 0 is a ray
  /// Multiplies WorldDef::gravity (0: a straight line). The speed gained by falling is capped at
  /// max_linear_speed, and a projectile whose flight leaves the finite range is removed.
  Real gravity_scale = 1;
  Filter filter;                ///< hits bodies and shapes whose filters it collides with
  BodyId ignore;                ///< never hits this body (the shooter)
  std::uint64_t user_data = 0;  ///< returned in its hit event
};

struct ProjectileState {
  Vec3 position;  ///< m
  Vec3 velocity;  ///< m/s
  std::uint64_t user_data = 0;
};

/// A projectile touched something this step and was removed.
struct ProjectileHitEvent {
  ProjectileId projectile;
  ContactTarget target;  ///< the body or static shape hit
  Vec3 point;            ///< m, on the target's surface
  Vec3 normal;           ///< unit, from the target towards the projectile
  Vec3 velocity;         ///< m/s, the projectile's at impact
  Real time = 0;         ///< s after the step's start
  std::uint64_t user_data = 0;
};

}  // namespace ricochet::physics
