// A map's top-down view (server/src/web/map_view.h) from the real arena map: values checked by
// hand against server/maps/arena.toml, and each box's corners against the physics world the
// match builds from the same map.

#include "map_view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/map.h"

namespace ricochet::server::web::map_view_test {
namespace {

Map arena() {
  MapResult loaded = load_map_file(std::string(RICOCHET_SOURCE_DIR) + "/server/maps/arena.toml");
  if (auto* error = std::get_if<MapError>(&loaded)) ADD_FAILURE() << error->describe();
  return std::get<Map>(std::move(loaded));
}

TEST(MapView, TheArenaAsHandChecked) {
  const std::string json = map_view_json(arena());
  // +Y up: the ground is x-z; yaw 0 faces -Z, counter-clockwise seen from above.
  EXPECT_EQ(json.rfind("{\"map\":\"arena\",\"axes\":{\"up\":\"+y\",\"ground\":[\"x\",\"z\"],"
                       "\"yaw_zero\":\"-z\",\"yaw_turn\":\"ccw_from_above\"},"
                       "\"bounds\":{\"min\":[-22,-2,-22],\"max\":[22,12,22]},\"floor_y\":0,",
                       0),
            0u)
      << json.substr(0, 300);
  // The first wall (walls follow the boxes), from [-20.5, -20] to [20.5, -20], 1 m thick, 4 m high
  // on the floor.
  EXPECT_NE(json.find("{\"corners\":[[-20.5,-20.5],[20.5,-20.5],[20.5,-19.5],"
                      "[-20.5,-19.5]],\"y_min\":0,\"y_max\":4}"),
            std::string::npos);
  // The box at (-8, 0.75, 8), half extents 1.5 × 0.5 on the ground, yawed 30°: each corner
  // (±1.5, ±0.5) turned by x' = x cos30 + z sin30, z' = -x sin30 + z cos30.
  EXPECT_NE(json.find("{\"corners\":[[-9.549,8.317],[-6.951,6.817],[-6.451,7.683],[-9.049,9.183]],"
                      "\"y_min\":0,\"y_max\":1.5}"),
            std::string::npos);
  // The ramp: its four vertices on the ground, their heights, its two triangles.
  EXPECT_NE(json.find("\"meshes\":[{\"name\":\"ramp\",\"vertices\":[[5,-8],[5,-4],[11,-4],[11,-8]],"
                      "\"heights\":[0,0,2,2],\"triangles\":[[0,1,2],[0,2,3]]}]"),
            std::string::npos);
  // The first spawn: -135° is -2.3562 rad.
  EXPECT_NE(json.find("\"spawns\":[{\"position\":[-16,0.45,-16],\"yaw\":-2.3562,\"team\":\"red\"}"),
            std::string::npos);
  EXPECT_NE(json.find("{\"position\":[-16,0.45,0],\"yaw\":-1.5708,\"team\":null}"),
            std::string::npos);
  EXPECT_EQ(json.back(), '}');
}

/// Whether `point` is over `box` seen from above (walls meet and overlap at their ends).
bool covers(const MapBox& box, const physics::Vec3& point) {
  const physics::Vec3 d = point - box.center_m;
  const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
  // The box's local x and z of `point`: the yaw about +Y undone.
  const double local_x = c * d.x() - s * d.z(), local_z = s * d.x() + c * d.z();
  return std::abs(local_x) <= box.half_extents_m.x() && std::abs(local_z) <= box.half_extents_m.z();
}

TEST(MapView, BoxCornersAreWhereThePhysicsWorldHasTheBoxes) {
  const Map map = arena();
  auto world = physics::World::create(physics::profiles::arena_players());
  ASSERT_TRUE(world.ok());
  ASSERT_TRUE(add_map_to_world(map, world.value()).ok());
  const std::string json = map_view_json(map);
  // A ray straight down 2 cm inside each corner (towards the centre) lands on the box's top; 2 cm
  // outside it passes by (the floor, or another box lower than this one's top), unless another
  // box is there.
  std::size_t at = json.find("\"boxes\":[");
  for (const MapBox& box : map.boxes) {
    at = json.find("{\"corners\":[[", at);
    ASSERT_NE(at, std::string::npos);
    at += 13;
    for (int corner = 0; corner < 4; ++corner) {
      std::size_t end = 0;
      const double x = std::stod(json.substr(at), &end);
      at += end + 1;
      const double z = std::stod(json.substr(at), &end);
      at += end + 3;  // "],["
      const physics::Vec3 point(static_cast<physics::Real>(x), 50, static_cast<physics::Real>(z));
      const physics::Vec3 centre(box.center_m.x(), 50, box.center_m.z());
      const physics::Vec3 inward = (centre - point).normalized() * physics::Real(0.02);
      const physics::Real top = box.center_m.y() + box.half_extents_m.y();
      physics::RayHit hit;
      ASSERT_TRUE(
          world.value().ray_cast_closest(point + inward, physics::Vec3(0, -1, 0), 100, {}, hit));
      EXPECT_NEAR(hit.point.y(), top, 1e-3) << "corner " << corner << " at " << x << ", " << z;
      if (world.value().ray_cast_closest(point - inward, physics::Vec3(0, -1, 0), 100, {}, hit) &&
          !std::any_of(map.boxes.begin(), map.boxes.end(), [&](const MapBox& other) {
            return &other != &box && covers(other, point - inward);
          })) {
        EXPECT_LT(hit.point.y(), top - 0.01) << "corner " << corner << " at " << x << ", " << z;
      }
    }
  }
}

}  // namespace
}  // namespace ricochet::server::web::map_view_test
