/// The arena scene (arena_scene.h).

#include "arena_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::bench {

namespace profiles = ricochet::physics::profiles;

const char* arena_model_name(ArenaModel m) {
  return m == ArenaModel::Full ? "full" : "arena_players";
}

namespace {

constexpr int kPlayers = kArenaPlayers;
constexpr int kProjectiles = kArenaBullets;
constexpr rp::Real kHalfWidth = 20;         ///< m, arena half extent
constexpr rp::Real kPlayerSpeed = 6;        ///< m/s, scripted run speed
constexpr rp::Real kProjectileSpeed = 300;  ///< m/s
constexpr rp::Real kSpentSpeed = 50;        ///< m/s, a slower bullet body is retired

using Model = ArenaModel;

/// Deterministic pseudo-random numbers (the same sequence for both models).
struct Lcg {
  std::uint64_t state;
  double next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  }
};

struct Arena {
  rp::World world;
  std::vector<rp::BodyId> players;
  std::vector<rp::BodyId> bullet_bodies;  ///< full model
  std::vector<rp::ProjectileId> bullets;  ///< profile
  int live_bullets() const { return static_cast<int>(bullet_bodies.size() + bullets.size()); }
};

rp::BodyDef player_def(Model m, const rp::Vec3& p) {
  rp::BodyDef def = profiles::player(p);
  if (m == Model::Full) {  // everything on: spin, swept, sleeps when it can
    def.lock_rotation = false;
    def.fast = true;
    def.allow_sleep = true;
  }
  return def;
}

rp::BodyDef full_bullet_def(const rp::Vec3& p, const rp::Vec3& v) {
  rp::BodyDef def = profiles::bullet_body(p, v);
  def.lock_rotation = false;
  def.filter.mask = 0xFFFFFFFFu;  // bullets also hit each other
  return def;
}

bool outside(const rp::Vec3& p) {
  return std::abs(p.x()) > kHalfWidth || std::abs(p.z()) > kHalfWidth || p.y() < 0 || p.y() > 10;
}

Arena build(Model m, ArenaFloor floor) {
  Arena a{
      rp::World::create(m == Model::Full ? profiles::physics_props() : profiles::arena_players())
          .value(),
      {},
      {},
      {}};
  rp::World& w = a.world;
  if (floor == ArenaFloor::Plane) {
    (void)w.add_plane({.normal = rp::Vec3::UnitY(), .offset = 0});
  } else {  // 100 × 100 cells = kArenaMeshTriangles, 5 cm bumps under the players
    (void)w.add_mesh(heightfield(100, kHalfWidth + 2, rp::Real(0.05)));
  }
  const rp::Real h = kHalfWidth;
  for (int side = 0; side < 4; ++side) {  // four 1 m thick, 4 m high walls
    const rp::Real s = side % 2 == 0 ? rp::Real(1) : rp::Real(-1);
    const rp::Vec3 center = side < 2 ? rp::Vec3(s * (h + rp::Real(0.5)), 2, 0)
                                     : rp::Vec3(0, 2, s * (h + rp::Real(0.5)));
    const rp::Vec3 half = side < 2 ? rp::Vec3(rp::Real(0.5), 2, h + 1) : rp::Vec3(h + 1, 2, 0.5);
    (void)w.add_box({.center = center, .half_extents = half});
  }
  for (int i = 0; i < 9; ++i) {  // pillars on a 3×3 grid
    const rp::Vec3 c((i % 3 - 1) * rp::Real(10), 2, (i / 3 - 1) * rp::Real(10));
    (void)w.add_box({.center = c, .half_extents = rp::Vec3(1, 2, 1)});
  }
  for (int i = 0; i < kPlayers; ++i) {
    const rp::Vec3 p((i % 8 - rp::Real(3.5)) * 4 + 2, rp::Real(0.4),
                     (i / 8 - rp::Real(3.5)) * 4 + 2);
    a.players.push_back(w.create_body(player_def(m, p)).value());
  }
  return a;
}

/// Player i's scripted horizontal velocity at step n: a run whose heading turns slowly.
rp::Vec3 steer(int i, int n) {
  const double heading = 0.7 * i + 0.02 * n * (1 + i % 3);
  return rp::Vec3(static_cast<rp::Real>(kPlayerSpeed * std::cos(heading)), 0,
                  static_cast<rp::Real>(kPlayerSpeed * std::sin(heading)));
}

}  // namespace

rp::MeshDef heightfield(int cells, rp::Real half_width_m, rp::Real amplitude_m) {
  rp::MeshDef mesh;
  const int n = cells + 1;  // vertices per side
  const rp::Real spacing = 2 * half_width_m / static_cast<rp::Real>(cells);
  for (int z = 0; z < n; ++z) {
    for (int x = 0; x < n; ++x) {
      const rp::Real px = -half_width_m + spacing * static_cast<rp::Real>(x);
      const rp::Real pz = -half_width_m + spacing * static_cast<rp::Real>(z);
      const rp::Real py = amplitude_m * std::sin(rp::Real(0.7) * px) * std::cos(rp::Real(0.5) * pz);
      mesh.vertices.emplace_back(px, py, pz);
    }
  }
  for (int z = 0; z < cells; ++z) {
    for (int x = 0; x < cells; ++x) {
      const auto v = static_cast<std::uint32_t>(z * n + x);
      const auto below = static_cast<std::uint32_t>(n);
      // Counter-clockwise seen from above, so the face normals point up.
      mesh.indices.insert(mesh.indices.end(),
                          {v, v + below, v + 1, v + 1, v + below, v + below + 1});
    }
  }
  return mesh;
}

ArenaResult run_arena(ArenaModel m, int steps, const ArenaStep& step, ArenaFloor floor) {
  Arena a = build(m, floor);
  Lcg rng{12345};
  ArenaResult r;
  double total_ms = 0;
  for (int n = 0; n < steps; ++n) {
    // Game logic: steer players (keep their vertical speed), retire spent bullets, fire new.
    for (int i = 0; i < kPlayers; ++i) {
      const rp::Vec3 v = a.world.body_state(a.players[i]).value().linear_velocity;
      rp::Vec3 run_velocity = steer(i, n);
      run_velocity.y() = v.y();
      (void)a.world.set_linear_velocity(a.players[i], run_velocity);
    }
    std::erase_if(a.bullet_bodies, [&](rp::BodyId id) {
      const rp::BodyState b = a.world.body_state(id).value();
      const bool spent = outside(b.position) || b.linear_velocity.norm() < kSpentSpeed;
      if (spent) (void)a.world.destroy_body(id);
      return spent;
    });
    std::erase_if(a.bullets, [&](rp::ProjectileId id) {
      if (!a.world.is_valid(id)) return true;  // it hit something last step
      const bool spent = outside(a.world.projectile_state(id).value().position);
      if (spent) (void)a.world.destroy_projectile(id);
      return spent;
    });
    while (a.live_bullets() < kProjectiles) {
      const int shooter = static_cast<int>(rng.next() * kPlayers) % kPlayers;
      const double yaw = rng.next() * 6.283185307179586, pitch = (rng.next() - 0.5) * 0.1;
      const rp::Vec3 dir(static_cast<rp::Real>(std::cos(yaw) * std::cos(pitch)),
                         static_cast<rp::Real>(std::sin(pitch)),
                         static_cast<rp::Real>(std::sin(yaw) * std::cos(pitch)));
      const rp::Vec3 muzzle = a.world.body_state(a.players[shooter]).value().position +
                              dir * rp::Real(0.6) + rp::Vec3(0, rp::Real(0.3), 0);
      const rp::Vec3 velocity = dir * kProjectileSpeed;
      ++r.fired;
      if (m == Model::Full) {
        a.bullet_bodies.push_back(a.world.create_body(full_bullet_def(muzzle, velocity)).value());
      } else {
        a.bullets.push_back(
            a.world.create_projectile(profiles::bullet(muzzle, velocity, a.players[shooter]))
                .value());
      }
    }
    total_ms += step(a.world);
    const rp::StepProfile& p = a.world.profile();
    r.phases.broad_phase_ms += p.broad_phase_ms / steps;
    r.phases.narrow_phase_ms += p.narrow_phase_ms / steps;
    r.phases.solve_ms += p.solve_ms / steps;
    r.phases.integrate_ms += p.integrate_ms / steps;
    r.phases.continuous_ms += p.continuous_ms / steps;
    r.phases.projectiles_ms += p.projectiles_ms / steps;
    r.phases.sleep_ms += p.sleep_ms / steps;
    r.phases.events_ms += p.events_ms / steps;
    const auto is_player = [&](rp::BodyId id) {
      return std::find(a.players.begin(), a.players.end(), id) != a.players.end();
    };
    const auto is_bullet = [&](rp::BodyId id) {
      return std::find(a.bullet_bodies.begin(), a.bullet_bodies.end(), id) != a.bullet_bodies.end();
    };
    for (const rp::ContactBeginEvent& e : a.world.contact_begin_events()) {
      const rp::BodyId other = e.other.body;
      const bool bullet_on_player =
          (is_player(e.body) && is_bullet(other)) || (is_bullet(e.body) && is_player(other));
      if (bullet_on_player && e.approach_speed > kSpentSpeed) ++r.hits;
    }
    for (const rp::ProjectileHitEvent& e : a.world.projectile_hit_events())
      r.hits += is_player(e.target.body) ? 1 : 0;
  }
  r.ms_per_step = total_ms / steps;
  for (const rp::BodyId id : a.players)
    r.final_players.push_back(a.world.body_state(id).value().position);
  return r;
}

}  // namespace ricochet::bench
