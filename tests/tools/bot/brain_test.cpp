#include "ricochet/bot/brain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace ricochet::bot {
namespace {

constexpr std::uint32_t kFire = 1u << 1;

proto::QuantizedEntity entity(std::uint32_t id, Vec3 position) {
  proto::EntityState state;
  state.id = id;
  state.position_m = position;
  return proto::quantize(state, proto::QuantizationSpec{});
}

wire::PlayerStatus alive_with_ammo(int health = 100) {
  wire::PlayerStatus status;
  status.set_alive(true);
  status.set_health(health);
  for (const int ammo : {100, 10, 10}) status.add_ammo(ammo);
  return status;
}

TEST(Brain, APerfectShotAimsAtTheEnemyAndFires) {
  WorldView view{proto::QuantizationSpec{}};
  // The enemy stands 10 m along +X; yaw 0 looks along -Z, so +X is yaw -pi/2.
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {10, 1, 0})});
  Brain brain(1.0, 7);
  const wire::Input input = brain.decide(view, alive_with_ammo(), 0.0);
  EXPECT_NEAR(input.yaw(), -std::numbers::pi_v<float> / 2, 1e-3f);
  EXPECT_NEAR(input.pitch(), std::atan2(-0.25f, 10.0f), 1e-3f);  // from the eye, 0.25 m up
  EXPECT_TRUE(input.buttons() & kFire);
  EXPECT_LE(std::abs(input.move_right()), 127);
  EXPECT_LE(std::abs(input.move_forward()), 127);
}

TEST(Brain, LowSkillMissesByMoreThanHighSkill) {
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {0, 1, -10})});
  const auto mean_error = [&](double skill) {
    Brain brain(skill, 11);
    double sum = 0;
    for (int i = 0; i < 200; ++i) sum += std::abs(brain.decide(view, alive_with_ammo(), i).yaw());
    return sum / 200;
  };
  EXPECT_LT(mean_error(1.0), 1e-3);
  EXPECT_GT(mean_error(0.0), 0.05);
  EXPECT_LT(mean_error(0.8), mean_error(0.0));
}

TEST(Brain, DeadOrUnseenDoesNothing) {
  WorldView view{proto::QuantizationSpec{}};
  Brain brain(1.0, 3);
  EXPECT_EQ(brain.decide(view, alive_with_ammo(), 0).buttons(), 0u);  // no own entity yet
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {5, 1, 0})});
  wire::PlayerStatus dead = alive_with_ammo(0);
  dead.set_alive(false);
  const wire::Input input = brain.decide(view, dead, 0);
  EXPECT_EQ(input.buttons(), 0u);
  EXPECT_EQ(input.move_forward(), 0);
}

TEST(Brain, AHurtBotWalksToAKnownHealthPickup) {
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {0, 1, -12})});
  wire::GameEvent taken;
  taken.mutable_pickup()->set_pickup_index(0);
  taken.mutable_pickup()->set_kind(wire::PICKUP_KIND_HEALTH);
  taken.mutable_pickup()->set_entity_id(2);
  view.apply_event(taken);
  wire::GameEvent back = taken;
  back.mutable_pickup()->set_entity_id(0);
  view.apply_event(back);
  // Entity 2 left; the pickup it took is 12 m along -Z (yaw 0).
  view.apply_snapshot(2, 1, std::vector{entity(1, {0, 1, 0})});
  Brain brain(1.0, 5);
  const wire::Input input = brain.decide(view, alive_with_ammo(30), 0);
  EXPECT_NEAR(input.yaw(), 0.0f, 1e-3f);
  EXPECT_EQ(input.move_forward(), 127);
  EXPECT_EQ(input.move_right(), 0);
}

TEST(Brain, ExplosivesAreNotUsedAtPointBlank) {
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {2, 1, 0})});
  Brain brain(1.0, 9);
  for (int i = 0; i < 100; ++i) {
    const wire::Input input = brain.decide(view, alive_with_ammo(), 0.5 * i);
    EXPECT_TRUE(input.weapon_slot() == 0 || input.weapon_slot() == 1) << i;
  }
}

}  // namespace
}  // namespace ricochet::bot
