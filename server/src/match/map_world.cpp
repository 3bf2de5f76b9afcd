/// A parsed map's static geometry in a physics world (map.h).

#include <Eigen/Geometry>

#include "ricochet/server/map.h"

namespace ricochet::server {

physics::Status add_map_to_world(const Map& map, physics::World& world) {
  using physics::Real;
  if (map.floor_y_m) {
    physics::PlaneDef floor;
    floor.normal = physics::Vec3::UnitY();
    floor.offset = Real(*map.floor_y_m);
    const physics::Result<physics::ShapeId> added = world.add_plane(floor);
    if (!added.ok()) return added.error();
  }
  for (const MapBox& box : map.boxes) {
    physics::BoxDef def;
    def.center = box.center_m;
    def.orientation =
        physics::Quat(Eigen::AngleAxis<Real>(Real(box.yaw_rad), physics::Vec3::UnitY()));
    def.half_extents = box.half_extents_m;
    const physics::Result<physics::ShapeId> added = world.add_box(def);
    if (!added.ok()) return added.error();
  }
  for (const MapMesh& mesh : map.meshes) {
    physics::MeshDef def;
    def.vertices = mesh.vertices_m;
    def.indices = mesh.indices;
    const physics::Result<physics::ShapeId> added = world.add_mesh(def);
    if (!added.ok()) return added.error();
  }
  return {};
}

}  // namespace ricochet::server
