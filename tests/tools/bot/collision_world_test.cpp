// The join reply's collision world on the client (collision_world.h): a good one builds, every
// kind of bad one is refused with a message naming the item, and nothing non-finite gets in.
#include "ricochet/bot/collision_world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "collision_world_fixture.h"

namespace ricochet::bot::collision_world_test {
namespace {

std::string refusal(const wire::CollisionWorld& world) {
  auto built = build_prediction_world(world);
  const std::string* error = std::get_if<std::string>(&built);
  return error ? *error : std::string();
}

TEST(CollisionWorldCheck, AGoodWorldBuilds) {
  auto built = build_prediction_world(testing::arena_world());
  ASSERT_TRUE(std::holds_alternative<PredictionWorld>(built)) << std::get<std::string>(built);
  const PredictionWorld& world = std::get<PredictionWorld>(built);
  EXPECT_EQ(world.world.shape_count(), 3u);
  EXPECT_EQ(world.player.radius, physics::Real(0.4));
  EXPECT_EQ(world.player.material.friction, 0);
  EXPECT_EQ(world.motion.max_speed_mps, 7.0f);
  EXPECT_EQ(world.world.definition().gravity.y(), physics::Real(-9.81f));
}

TEST(CollisionWorldCheck, RefusesEachKindOfBadValueNamingIt) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    const char* expected;
    std::function<void(wire::CollisionWorld&)> spoil;
  };
  const Case cases[] = {
      {"movement rules missing", [](auto& w) { w.clear_movement(); }},
      {"movement max_speed_mps must be 0.1..100",
       [&](auto& w) { w.mutable_movement()->set_max_speed_mps(nan); }},
      {"player_radius_m must be 0.05..5", [](auto& w) { w.set_player_radius_m(0); }},
      {"player_mass_kg must be 1..10000", [&](auto& w) { w.set_player_mass_kg(inf); }},
      {"gravity_mps2 must have 3 values, got 2",
       [](auto& w) { w.mutable_gravity_mps2()->RemoveLast(); }},
      {"gravity_mps2.y must be finite", [](auto& w) { w.set_gravity_mps2(1, -1000); }},
      {"plane 1 normal.x must be finite",
       [&](auto& w) { w.mutable_planes(0)->set_normal(0, nan); }},
      {"plane 1 normal must not be zero", [](auto& w) { w.mutable_planes(0)->set_normal(1, 0); }},
      {"plane 1 offset_m must be", [&](auto& w) { w.mutable_planes(0)->set_offset_m(inf); }},
      {"box 1 center_m must have 3 values, got 4",
       [](auto& w) { w.mutable_boxes(0)->add_center_m(1); }},
      {"box 1 orientation length must be 1 +- 0.001",
       [](auto& w) { w.mutable_boxes(0)->set_orientation(3, 0.5f); }},
      {"box 1 half_extents_m.y must be 0.001..100000",
       [](auto& w) { w.mutable_boxes(0)->set_half_extents_m(1, -1); }},
      {"mesh 1 vertices_m must be a non-zero multiple of 3 floats, got 11",
       [](auto& w) { w.mutable_meshes(0)->mutable_vertices_m()->RemoveLast(); }},
      {"mesh 1 indices must be a non-zero multiple of 3, got 5",
       [](auto& w) { w.mutable_meshes(0)->mutable_indices()->RemoveLast(); }},
      {"mesh 1 index 9 is not below its 4 vertices",
       [](auto& w) { w.mutable_meshes(0)->set_indices(4, 9); }},
      {"mesh 1 vertex 2.z must be -100000..100000",
       [&](auto& w) { w.mutable_meshes(0)->set_vertices_m(5, nan); }},
      {"at most 16 planes, got 17",
       [](auto& w) {
         for (int k = 0; k < 16; ++k) *w.add_planes() = w.planes(0);
       }},
  };
  for (const Case& c : cases) {
    wire::CollisionWorld world = testing::arena_world();
    c.spoil(world);
    EXPECT_NE(refusal(world).find(c.expected), std::string::npos)
        << "expected \"" << c.expected << "\", got \"" << refusal(world) << "\"";
  }
}

TEST(CollisionWorldCheck, RefusesTooManyTrianglesInAll) {
  wire::CollisionWorld world = testing::arena_world();
  wire::CollisionMesh& big = *world.add_meshes();
  for (int k = 0; k < 9; ++k) big.add_vertices_m(float(k % 3));
  for (std::size_t k = 0; k < 3 * (proto::CollisionWorldLimits::kMaxTriangles + 1); ++k) {
    big.add_indices(static_cast<std::uint32_t>(k % 3));
  }
  EXPECT_NE(refusal(world).find("triangles in all meshes, mesh 2 goes past that"),
            std::string::npos)
      << refusal(world);
}

}  // namespace
}  // namespace ricochet::bot::collision_world_test
