#pragma once
/// The physics scenes whose snapshot streams snapshot-bench measures and ricochet-vectors records
/// (tests/vectors/snapshots_*.txt): each a world, its bodies in entity id order and the scripted
/// control that moves them.
///
///   spheres901  Fiedler's cube demo with spheres: 900 spheres (0.5 m) resting in a 30 x 30 grid
///               on a floor, one large kinematic sphere (2.5 m radius) driven through them on a
///               figure of eight at up to 4 m/s. Spheres and floor resist rolling, so a knocked
///               sphere rolls a metre or two and rests. The grid's spacing is the caller's
///               (kSpheresSpacing, or kSpheresDenseSpacing for a crowd the ball ploughs).
///   playersN    arena_players movement: N players running on scripted headings and jumping
///               now and then; client c's viewer is player c.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "ricochet/physics/world.h"
#include "ricochet/proto/quantize.h"

namespace ricochet::bench {

/// A physics scene: its world, its bodies in id order and how it moves.
struct SnapshotScene {
  std::string name;
  proto::QuantizationSpec spec;
  physics::World world;
  std::vector<physics::BodyId> bodies;  ///< entity id = index + 1
  /// Scripted control before each step; `moving` false while the scene rests.
  std::function<void(SnapshotScene&, int step, bool moving)> drive;
  /// Viewer position of client c, m.
  std::function<std::array<float, 3>(const SnapshotScene&, int client)> viewer;
  int clients = 1;
};

/// m between the sphere grid's centres: 0.3 m gaps.
inline constexpr physics::Real kSpheresSpacing = 1.3;
/// m, 5 cm gaps: the ball ploughs a crowd ahead of it.
inline constexpr physics::Real kSpheresDenseSpacing = 1.05;

/// The spheres scene named `name`, the grid `spacing` m apart; one client, viewing from the ball.
SnapshotScene spheres_scene(const std::string& name, physics::Real spacing);
/// `players` players in a 40 m arena, one client per player.
SnapshotScene players_scene(int players);

/// The world's entities this tick, quantised with the scene's spec, sorted by id.
void read_entities(const SnapshotScene& scene, std::vector<proto::QuantizedEntity>& out);

}  // namespace ricochet::bench
