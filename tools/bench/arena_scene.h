#pragma once
/// The arena scene shared by arena-bench and the physics study: 64 players and 256 bullets in a
/// walled 40 m arena with pillars, from scripted inputs (players steered by fixed velocity
/// scripts, bullets fired on a fixed pseudo-random schedule), in one of two models:
///
///   Full          physics_props world; players spin, are swept and may sleep; bullets are 10 g
///                 rigid bodies with continuous collision that also hit each other
///   ArenaPlayers  the arena_players profile (scene_profile.h): players without spin, bullets as
///                 swept projectiles (projectile.h) that never enter the contact pipeline
///
/// A bullet is retired when it leaves the arena, or (full model) slows below 50 m/s after
/// hitting something; a new one replaces it, so 256 are always in flight.

#include <functional>
#include <vector>

#include "ricochet/physics/world.h"

namespace ricochet::bench {

namespace rp = ricochet::physics;

enum class ArenaModel { Full, ArenaPlayers };

/// The arena's floor: an infinite plane, or a map-sized triangle mesh (a gently rolling
/// heightfield of kArenaMeshTriangles triangles) like the one a level file would hold.
enum class ArenaFloor { Plane, Mesh };

const char* arena_model_name(ArenaModel m);

inline constexpr int kArenaPlayers = 64;
inline constexpr int kArenaBullets = 256;
inline constexpr int kArenaMeshTriangles = 20000;

struct ArenaResult {
  double ms_per_step = 0;  ///< what the step function reported, per step
  rp::StepProfile phases;  ///< per-phase ms, averaged over the steps
  int hits = 0;   ///< bullet hits on players (full model: contact begins faster than 50 m/s)
  int fired = 0;  ///< bullets created
  std::vector<rp::Vec3> final_players;  ///< m
};

/// Steps the world once and returns the milliseconds to count (World::step only).
using ArenaStep = std::function<double(rp::World&)>;

ArenaResult run_arena(ArenaModel model, int steps, const ArenaStep& step,
                      ArenaFloor floor = ArenaFloor::Plane);

/// The mesh floor: a square heightfield of half width half_width_m, cells × cells quads (two
/// triangles each), heights within ±amplitude_m around y = 0.
rp::MeshDef heightfield(int cells, rp::Real half_width_m, rp::Real amplitude_m);

}  // namespace ricochet::bench
