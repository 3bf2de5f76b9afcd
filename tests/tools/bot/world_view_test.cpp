#include "ricochet/bot/world_view.h"

#include <gtest/gtest.h>

#include <vector>

namespace ricochet::bot::world_view_test {
namespace {

proto::QuantizedEntity entity(std::uint32_t id, Vec3 position, std::uint8_t flags = 0) {
  proto::EntityState state;
  state.id = id;
  state.position_m = position;
  state.flags = flags;
  return proto::quantize(state, proto::QuantizationSpec{});
}

TEST(WorldView, TheNearestEnemyIsALivingPlayerThatIsNotUs) {
  WorldView view{proto::QuantizationSpec{}};
  const std::vector<proto::QuantizedEntity> world{
      entity(1, {0, 1, 0}),
      entity(2, {1, 1, 0}, proto::kEntityDead),
      entity(3, {2, 1, 0}, proto::kind_flags(proto::EntityKind::Rocket)),
      entity(4, {3, 1, 0}, proto::kEntityDisconnected),
      entity(5, {9, 1, 0}),
      entity(6, {6, 1, 0}),
  };
  view.apply_snapshot(100, 1, world);
  ASSERT_NE(view.own(), nullptr);
  EXPECT_NEAR(view.own()->position_m[1], 1.0f, 1e-3f);
  ASSERT_NE(view.nearest_enemy(), nullptr);
  EXPECT_EQ(view.nearest_enemy()->id, 6u);
  EXPECT_EQ(view.find(3)->kind(), proto::EntityKind::Rocket);
  EXPECT_EQ(view.find(7), nullptr);
}

TEST(WorldView, TeamMatesAreNotEnemies) {
  WorldView view{proto::QuantizationSpec{}};
  for (const auto& [id, team] : {std::pair{1u, wire::TEAM_RED}, std::pair{2u, wire::TEAM_RED},
                                 std::pair{3u, wire::TEAM_BLUE}}) {
    wire::GameEvent event;
    event.mutable_spawned()->set_entity_id(id);
    event.mutable_spawned()->set_team(team);
    view.apply_event(event);
  }
  view.apply_snapshot(
      5, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {1, 1, 0}), entity(3, {8, 1, 0})});
  ASSERT_NE(view.nearest_enemy(), nullptr);
  EXPECT_EQ(view.nearest_enemy()->id, 3u);
}

TEST(WorldView, LearnsSpawnPointsAndPickupPlacesFromEvents) {
  WorldView view{proto::QuantizationSpec{}};
  wire::GameEvent spawned;
  spawned.mutable_spawned()->set_entity_id(2);
  for (const float v : {5.0f, 0.45f, -3.0f}) spawned.mutable_spawned()->add_position(v);
  view.apply_event(spawned);
  view.apply_event(spawned);  // the same place once
  ASSERT_EQ(view.spawn_points().size(), 1u);
  EXPECT_EQ(view.spawn_points()[0][2], -3.0f);

  // A spawn with a position that is not three finite numbers is ignored.
  wire::GameEvent broken;
  broken.mutable_spawned()->add_position(1.0f);
  view.apply_event(broken);
  EXPECT_EQ(view.spawn_points().size(), 1u);

  view.apply_snapshot(10, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {7, 0.45f, 7})});
  wire::GameEvent taken;
  taken.mutable_pickup()->set_pickup_index(3);
  taken.mutable_pickup()->set_kind(wire::PICKUP_KIND_HEALTH);
  taken.mutable_pickup()->set_entity_id(2);
  view.apply_event(taken);
  const KnownPickup& pickup = view.pickups().at(3);
  EXPECT_FALSE(pickup.up);
  ASSERT_TRUE(pickup.position_m);
  EXPECT_NEAR((*pickup.position_m)[0], 7.0f, 1e-3f);
  wire::GameEvent back;
  back.mutable_pickup()->set_pickup_index(3);
  back.mutable_pickup()->set_kind(wire::PICKUP_KIND_HEALTH);
  view.apply_event(back);
  EXPECT_TRUE(view.pickups().at(3).up);
  EXPECT_TRUE(view.pickups().at(3).position_m);
}

}  // namespace
}  // namespace ricochet::bot::world_view_test
