#include "ricochet/bot/brain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "ricochet/proto/input_wire.h"

namespace ricochet::bot::brain_test {
namespace {

/// The shipped weapons as a join reply gives them.
wire::JoinMatchReply shipped_weapons() {
  wire::JoinMatchReply reply;
  const struct {
    wire::Weapon weapon;
    float speed_mps;
    float gravity_y;
  } weapons[] = {{wire::WEAPON_RIFLE, 0, 0},
                 {wire::WEAPON_ROCKET_LAUNCHER, 25, 0},
                 {wire::WEAPON_GRENADE_LAUNCHER, 15, -9.81f}};
  for (const auto& [weapon, speed, gravity_y] : weapons) {
    wire::WeaponSpec& spec = *reply.add_weapons();
    spec.set_weapon(weapon);
    spec.set_projectile_speed_mps(speed);
    for (const float g : {0.0f, gravity_y, 0.0f}) spec.add_gravity_mps2(g);
  }
  return reply;
}

Brain armed_brain(double skill, std::uint64_t seed) {
  Brain brain(skill, seed);
  std::string error;
  brain.set_weapons(arsenal_of(shipped_weapons(), error).value());
  return brain;
}

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
  Brain brain = armed_brain(1.0, 7);
  const wire::Input input = brain.decide(view, alive_with_ammo(), 0.0);
  EXPECT_NEAR(input.yaw(), -std::numbers::pi_v<float> / 2, 1e-3f);
  EXPECT_NEAR(input.pitch(), std::atan2(-0.25f, 10.0f), 1e-3f);  // from the eye, 0.25 m up
  EXPECT_TRUE(input.buttons() & proto::kButtonFire);
  EXPECT_LE(std::abs(input.move_right()), 127);
  EXPECT_LE(std::abs(input.move_forward()), 127);
}

TEST(Brain, LowSkillMissesByMoreThanHighSkill) {
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {0, 1, -10})});
  const auto mean_error = [&](double skill) {
    Brain brain = armed_brain(skill, 11);
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
  Brain brain = armed_brain(1.0, 3);
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
  Brain brain = armed_brain(1.0, 5);
  const wire::Input input = brain.decide(view, alive_with_ammo(30), 0);
  EXPECT_NEAR(input.yaw(), 0.0f, 1e-3f);
  EXPECT_EQ(input.move_forward(), 127);
  EXPECT_EQ(input.move_right(), 0);
}

TEST(Brain, ExplosivesAreNotUsedAtPointBlank) {
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {2, 1, 0})});
  Brain brain = armed_brain(1.0, 9);
  for (int i = 0; i < 100; ++i) {
    const wire::Input input = brain.decide(view, alive_with_ammo(), 0.5 * i);
    EXPECT_TRUE(input.weapon_slot() == 0 || input.weapon_slot() == 1) << i;
  }
}

TEST(Arsenal, TheJoinReplysWeaponsGiveSpeedAndDrop) {
  std::string error;
  const std::optional<Arsenal> arsenal = arsenal_of(shipped_weapons(), error);
  ASSERT_TRUE(arsenal) << error;
  EXPECT_EQ((*arsenal)[0].speed_mps, 0.0f);
  EXPECT_EQ((*arsenal)[1].speed_mps, 25.0f);
  EXPECT_EQ((*arsenal)[1].drop_mps2, 0.0f);
  EXPECT_EQ((*arsenal)[2].speed_mps, 15.0f);
  EXPECT_FLOAT_EQ((*arsenal)[2].drop_mps2, 9.81f);
}

TEST(Arsenal, AReplyWithoutEveryWeaponIsRefused) {
  std::string error;
  wire::JoinMatchReply reply = shipped_weapons();
  reply.mutable_weapons()->RemoveLast();
  EXPECT_FALSE(arsenal_of(reply, error));
  EXPECT_EQ(error, "no spec for weapon 3");
  EXPECT_FALSE(arsenal_of(wire::JoinMatchReply{}, error));  // an older server sends none
}

TEST(Arsenal, AWrongWeaponIsRefusedWithAReason) {
  const auto refused = [](auto change) {
    wire::JoinMatchReply reply = shipped_weapons();
    change(reply);
    std::string error;
    EXPECT_FALSE(arsenal_of(reply, error));
    return error;
  };
  EXPECT_EQ(refused([](wire::JoinMatchReply& r) {
              r.mutable_weapons(2)->set_weapon(wire::WEAPON_RIFLE);
            }),
            "weapon WEAPON_RIFLE given twice");
  EXPECT_EQ(refused([](wire::JoinMatchReply& r) {
              r.mutable_weapons(1)->set_weapon(static_cast<wire::Weapon>(9));
            }),
            "weapon 9 is not 1..3");
  EXPECT_NE(refused([](wire::JoinMatchReply& r) {
              r.mutable_weapons(1)->set_projectile_speed_mps(std::nanf(""));
            }).find("projectile_speed_mps"),
            std::string::npos);
  EXPECT_NE(refused([](wire::JoinMatchReply& r) {
              r.mutable_weapons(2)->set_gravity_mps2(1, INFINITY);
            }).find("gravity_mps2"),
            std::string::npos);
  EXPECT_NE(refused([](wire::JoinMatchReply& r) {
              r.mutable_weapons(2)->clear_gravity_mps2();
            }).find("3 values"),
            std::string::npos);
}

TEST(Brain, AGrenadeIsLobbedByTheReplysGravity) {
  // Only grenades left: the bot lobs them, higher under a stronger gravity.
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(1, 1, std::vector{entity(1, {0, 1, 0}), entity(2, {10, 1.25f, 0})});
  wire::PlayerStatus status;
  status.set_alive(true);
  status.set_health(100);
  for (const int ammo : {0, 0, 10}) status.add_ammo(ammo);
  const auto pitch_under = [&](float gravity_y) {
    wire::JoinMatchReply reply = shipped_weapons();
    reply.mutable_weapons(2)->set_gravity_mps2(1, gravity_y);
    std::string error;
    Brain brain(1.0, 1);
    brain.set_weapons(arsenal_of(reply, error).value());
    const wire::Input input = brain.decide(view, status, 0);
    EXPECT_EQ(input.weapon_slot(), 3u);
    return input.pitch();
  };
  // Level with the eye: the pitch is the arc's alone, 0.5 asin(d g / v^2).
  EXPECT_NEAR(pitch_under(-9.81f), 0.5f * std::asin(10 * 9.81f / (15 * 15)), 1e-3f);
  EXPECT_NEAR(pitch_under(-5.0f), 0.5f * std::asin(10 * 5.0f / (15 * 15)), 1e-3f);
}

}  // namespace
}  // namespace ricochet::bot::brain_test
