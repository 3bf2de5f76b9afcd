/// A map's collision world for the join reply (collision_world.h).

#include "ricochet/server/collision_world.h"

#include <Eigen/Geometry>

#include "ricochet/server/weapons.h"

namespace ricochet::server {

namespace {

template <class Field>
void put(const physics::Vec3& v, Field& out) {
  for (int axis = 0; axis < 3; ++axis) out.Add(static_cast<float>(v[axis]));
}

}  // namespace

std::shared_ptr<const wire::CollisionWorld> collision_world(const Map& map,
                                                            const MovementConfig& movement) {
  auto world = std::make_shared<wire::CollisionWorld>();
  // The same shapes, in the same order, as add_map_to_world().
  if (map.floor_y_m) {
    wire::CollisionPlane& floor = *world->add_planes();
    put(physics::Vec3::UnitY(), *floor.mutable_normal());
    floor.set_offset_m(*map.floor_y_m);
  }
  for (const MapBox& box : map.boxes) {
    wire::CollisionBox& out = *world->add_boxes();
    put(box.center_m, *out.mutable_center_m());
    const physics::Quat q(
        Eigen::AngleAxis<physics::Real>(physics::Real(box.yaw_rad), physics::Vec3::UnitY()));
    for (const physics::Real c : {q.x(), q.y(), q.z(), q.w()}) {
      out.add_orientation(static_cast<float>(c));
    }
    put(box.half_extents_m, *out.mutable_half_extents_m());
  }
  for (const MapMesh& mesh : map.meshes) {
    wire::CollisionMesh& out = *world->add_meshes();
    for (const physics::Vec3& vertex : mesh.vertices_m) put(vertex, *out.mutable_vertices_m());
    out.mutable_indices()->Add(mesh.indices.begin(), mesh.indices.end());
  }
  const physics::BodyDef player = player_body_def(physics::Vec3::Zero());
  world->set_player_radius_m(static_cast<float>(player.radius));
  world->set_player_mass_kg(static_cast<float>(player.mass));
  put(combat_world_def().gravity, *world->mutable_gravity_mps2());
  wire::MovementRules& rules = *world->mutable_movement();
  rules.set_max_speed_mps(movement.max_speed_mps);
  rules.set_ground_acceleration(movement.ground_acceleration);
  rules.set_air_acceleration(movement.air_acceleration);
  rules.set_friction(movement.friction);
  rules.set_stop_speed_mps(movement.stop_speed_mps);
  rules.set_jump_speed_mps(movement.jump_speed_mps);
  rules.set_ground_max_slope_deg(movement.ground_max_slope_deg);
  rules.set_ground_probe_m(movement.ground_probe_m);
  if (world->ByteSizeLong() > kMaxCollisionWorldBytes) return nullptr;
  return world;
}

}  // namespace ricochet::server
