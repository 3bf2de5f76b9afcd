#pragma once
/// A small collision world as a server would send it: a floor at y = 0, a wall box turned 30°
/// about +Y, a ramp mesh, the default player and movement rules.

#include <cmath>

#include "ricochet/wire/world.pb.h"

namespace ricochet::bot::testing {

inline wire::CollisionWorld arena_world() {
  wire::CollisionWorld world;
  wire::CollisionPlane& floor = *world.add_planes();
  for (const float c : {0.0f, 1.0f, 0.0f}) floor.add_normal(c);
  floor.set_offset_m(0);
  wire::CollisionBox& wall = *world.add_boxes();
  for (const float c : {6.0f, 1.0f, -4.0f}) wall.add_center_m(c);
  const float half_turn = 0.2617994f;  // 15°: a 30° turn about +Y
  for (const float c : {0.0f, std::sin(half_turn), 0.0f, std::cos(half_turn)}) {
    wall.add_orientation(c);
  }
  for (const float c : {0.25f, 1.0f, 3.0f}) wall.add_half_extents_m(c);
  wire::CollisionMesh& ramp = *world.add_meshes();
  for (const float c : {-2.0f, 0.0f, 2.0f, 2.0f, 0.0f, 2.0f, 2.0f, 1.5f, 8.0f, -2.0f, 1.5f, 8.0f}) {
    ramp.add_vertices_m(c);
  }
  for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) ramp.add_indices(i);
  world.set_player_radius_m(0.4f);
  world.set_player_mass_kg(80);
  for (const float c : {0.0f, -9.81f, 0.0f}) world.add_gravity_mps2(c);
  wire::MovementRules& rules = *world.mutable_movement();
  rules.set_max_speed_mps(7);
  rules.set_ground_acceleration(10);
  rules.set_air_acceleration(1);
  rules.set_friction(6);
  rules.set_stop_speed_mps(2);
  rules.set_jump_speed_mps(5);
  rules.set_ground_max_slope_deg(50);
  rules.set_ground_probe_m(0.05f);
  return world;
}

}  // namespace ricochet::bot::testing
