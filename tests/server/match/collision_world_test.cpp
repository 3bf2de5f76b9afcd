// The collision world a join reply carries (collision_world.h): the map's shapes in the order
// add_map_to_world() adds them, the player's body, gravity and the movement rules; a world too
// large for the reply is left out.
#include "ricochet/server/collision_world.h"

#include <gtest/gtest.h>

#include <variant>

#include "ricochet/server/weapons.h"

namespace ricochet::server::collision_world_test {
namespace {

Map arena() {
  auto loaded = load_map_file(RICOCHET_SOURCE_DIR "/server/maps/arena.toml");
  if (auto* error = std::get_if<MapError>(&loaded)) ADD_FAILURE() << error->describe();
  return std::get<Map>(std::move(loaded));
}

TEST(CollisionWorld, CarriesTheMapAndTheRules) {
  const Map map = arena();
  MovementConfig movement;
  movement.max_speed_mps = 8.5f;
  const auto world = collision_world(map, movement);
  ASSERT_TRUE(world != nullptr);
  ASSERT_EQ(world->planes_size(), map.floor_y_m ? 1 : 0);
  if (map.floor_y_m) {
    EXPECT_EQ(world->planes(0).offset_m(), *map.floor_y_m);
    EXPECT_EQ(world->planes(0).normal(1), 1.0f);
  }
  ASSERT_EQ(world->boxes_size(), static_cast<int>(map.boxes.size()));
  ASSERT_FALSE(map.boxes.empty());
  const MapBox& last = map.boxes.back();
  const wire::CollisionBox& sent = world->boxes(world->boxes_size() - 1);
  EXPECT_EQ(sent.center_m(0), static_cast<float>(last.center_m.x()));
  EXPECT_EQ(sent.half_extents_m(2), static_cast<float>(last.half_extents_m.z()));
  ASSERT_EQ(sent.orientation_size(), 4);
  EXPECT_NEAR(sent.orientation(3), std::cos(last.yaw_rad / 2), 1e-6);  // w of a turn about +Y
  ASSERT_EQ(world->meshes_size(), static_cast<int>(map.meshes.size()));
  for (int m = 0; m < world->meshes_size(); ++m) {
    EXPECT_EQ(world->meshes(m).vertices_m_size(),
              static_cast<int>(3 * map.meshes[m].vertices_m.size()));
    EXPECT_EQ(world->meshes(m).indices_size(), static_cast<int>(map.meshes[m].indices.size()));
  }
  EXPECT_EQ(world->player_radius_m(),
            static_cast<float>(player_body_def(physics::Vec3::Zero()).radius));
  EXPECT_EQ(world->player_mass_kg(), 80.0f);
  ASSERT_EQ(world->gravity_mps2_size(), 3);
  EXPECT_EQ(world->gravity_mps2(1), static_cast<float>(combat_world_def().gravity.y()));
  EXPECT_EQ(world->movement().max_speed_mps(), 8.5f);
  EXPECT_EQ(world->movement().ground_probe_m(), movement.ground_probe_m);
  EXPECT_LE(world->ByteSizeLong(), kMaxCollisionWorldBytes);
}

TEST(CollisionWorld, ATooLargeWorldIsLeftOut) {
  Map map = arena();
  MapMesh big;
  big.name = "big";
  for (std::uint32_t k = 0; k < 6000; ++k) {
    big.vertices_m.push_back(physics::Vec3(float(k % 50), 0, float(k / 50)));
    big.indices.insert(big.indices.end(), {k, (k + 1) % 6000, (k + 2) % 6000});
  }
  map.meshes.push_back(std::move(big));
  EXPECT_TRUE(collision_world(map, MovementConfig{}) == nullptr);
}

}  // namespace
}  // namespace ricochet::server::collision_world_test
