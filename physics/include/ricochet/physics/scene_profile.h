#pragma once
/// Scene profiles: ready-made feature sets so a scene models only what it requires. A profile is
/// a WorldDef (which kernels the step runs) plus body definitions (which bodies pay for spin and
/// continuous collision). Start from one and change what your scene needs differently.
///
/// Measured against each other on the same 64-player + 256-projectile arena by
/// tools/bench/arena_bench.cpp (results in tools/bench/results/arena.jsonl).

#include <cstdint>

#include "ricochet/physics/body.h"
#include "ricochet/physics/projectile.h"
#include "ricochet/physics/world_def.h"

namespace ricochet::physics::profiles {

/// Collision layers used by the profiles' body definitions.
enum Layer : std::uint32_t {
  kLayerStatic = 1u << 0,  ///< arena geometry (static shapes keep the default layer 1)
  kLayerPlayer = 1u << 1,
  kLayerProjectile = 1u << 2,
  kLayerProp = 1u << 3,
};

/// Players and bullets in an arena: no spin (players are upright capsules' stand-ins), linear
/// friction only, no rolling resistance, no restitution, 4 iterations, no sleeping (players are
/// always moving), continuous collision only for bodies flagged fast. Bullets are projectiles
/// (bullet()), which never enter the contact pipeline.
WorldDef arena_players();

/// Everything on, as WorldDef{} with sleeping: props that tumble, roll, bounce and rest.
WorldDef physics_props();

/// A player: 0.4 m radius, 80 kg, locked rotation, never sleeps; collides with the arena,
/// other players and projectiles.
BodyDef player(const Vec3& position);

/// A bullet: a 2 cm swept projectile (World::create_projectile), no gravity over arena
/// distances; hits the arena, players and props, never other bullets. `shooter` is never hit.
ProjectileDef bullet(const Vec3& position, const Vec3& velocity, BodyId shooter = {});

/// The same bullet as a rigid body (10 g, continuous collision), for when it must bounce or push.
BodyDef bullet_body(const Vec3& position, const Vec3& velocity);

/// A prop: 0.5 m radius, 5 kg, full rotation, collides with everything.
BodyDef prop(const Vec3& position);

}  // namespace ricochet::physics::profiles
