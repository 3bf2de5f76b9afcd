/// A map's static geometry as a top-down JSON document (map_view.h).

#include "map_view.h"

#include <Eigen/Geometry>

#include "json_out.h"

namespace ricochet::server::web {

namespace {

std::array<float, 3> to_array(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

void append_xz(std::string& out, const physics::Vec3& point) {
  out += '[';
  append_number(out, static_cast<double>(point.x()));
  out += ',';
  append_number(out, static_cast<double>(point.z()));
  out += ']';
}

const char* pickup_name(PickupKind kind) {
  switch (kind) {
    case PickupKind::Health:
      return "health";
    case PickupKind::Armor:
      return "armor";
    case PickupKind::Ammo:
      return "ammo";
  }
  return "unknown";
}

/// The box's four ground corners, rotated by its yaw as add_map_to_world rotates it.
void append_box(std::string& out, const MapBox& box) {
  using physics::Real;
  const physics::Quat yaw(Eigen::AngleAxis<Real>(Real(box.yaw_rad), physics::Vec3::UnitY()));
  const Real hx = box.half_extents_m.x(), hz = box.half_extents_m.z();
  const std::array<physics::Vec3, 4> corners = {physics::Vec3(-hx, 0, -hz),
                                                physics::Vec3(hx, 0, -hz), physics::Vec3(hx, 0, hz),
                                                physics::Vec3(-hx, 0, hz)};
  out += "{\"corners\":[";
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if (k > 0) out += ',';
    append_xz(out, box.center_m + yaw * corners[k]);
  }
  out += "],\"y_min\":";
  append_number(out, static_cast<double>(box.center_m.y() - box.half_extents_m.y()));
  out += ",\"y_max\":";
  append_number(out, static_cast<double>(box.center_m.y() + box.half_extents_m.y()));
  out += '}';
}

void append_mesh(std::string& out, const MapMesh& mesh) {
  out += "{\"name\":";
  append_string(out, mesh.name);
  out += ",\"vertices\":[";
  for (std::size_t k = 0; k < mesh.vertices_m.size(); ++k) {
    if (k > 0) out += ',';
    append_xz(out, mesh.vertices_m[k]);
  }
  out += "],\"heights\":[";
  for (std::size_t k = 0; k < mesh.vertices_m.size(); ++k) {
    if (k > 0) out += ',';
    append_number(out, static_cast<double>(mesh.vertices_m[k].y()));
  }
  out += "],\"triangles\":[";
  for (std::size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
    if (k > 0) out += ',';
    out += '[' + std::to_string(mesh.indices[k]) + ',' + std::to_string(mesh.indices[k + 1]) + ',' +
           std::to_string(mesh.indices[k + 2]) + ']';
  }
  out += "]}";
}

}  // namespace

std::string map_view_json(const Map& map) {
  std::string out = "{\"map\":";
  append_string(out, map.name);
  out +=
      ",\"axes\":{\"up\":\"+y\",\"ground\":[\"x\",\"z\"],\"yaw_zero\":\"-z\","
      "\"yaw_turn\":\"ccw_from_above\"},\"bounds\":{\"min\":";
  append_vec3(out, to_array(map.bounds_min_m));
  out += ",\"max\":";
  append_vec3(out, to_array(map.bounds_max_m));
  out += "},\"floor_y\":";
  if (map.floor_y_m) {
    append_number(out, *map.floor_y_m);
  } else {
    out += "null";
  }
  out += ",\"boxes\":";
  append_array(out, map.boxes, append_box);
  out += ",\"meshes\":";
  append_array(out, map.meshes, append_mesh);
  out += ",\"spawns\":";
  append_array(out, map.spawns, [](std::string& o, const MapSpawn& spawn) {
    o += "{\"position\":";
    append_vec3(o, to_array(spawn.position_m));
    o += ",\"yaw\":";
    append_number(o, spawn.yaw_rad, 4);
    o += ",\"team\":";
    append_team(o, spawn.team);
    o += '}';
  });
  out += ",\"pickups\":";
  append_array(out, map.pickups, [](std::string& o, const MapPickup& pickup) {
    o += "{\"kind\":\"";
    o += pickup_name(pickup.kind);
    o += "\",\"position\":";
    append_vec3(o, to_array(pickup.position_m));
    o += '}';
  });
  out += ",\"kill_volumes\":";
  append_array(out, map.kill_volumes, [](std::string& o, const MapKillVolume& volume) {
    o += "{\"name\":";
    append_string(o, volume.name);
    o += ",\"min\":";
    append_vec3(o, to_array(volume.min_m));
    o += ",\"max\":";
    append_vec3(o, to_array(volume.max_m));
    o += '}';
  });
  out += '}';
  return out;
}

}  // namespace ricochet::server::web
