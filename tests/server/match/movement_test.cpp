// Player movement on the physics core: expected speeds and heights from the movement config.

#include "ricochet/server/movement.h"

#include <gtest/gtest.h>

#include <cmath>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server::movement_test {
namespace {

using physics::Real;
using physics::Vec3;

constexpr float kDt = 1.0f / 60;
constexpr Real kRadius = Real(0.4);

/// A floor at y = 0 (and optionally a ramp) and one player on it, moved as the match moves it.
class MovementWorld {
 public:
  explicit MovementWorld(const Vec3& start = Vec3(0, kRadius, 0))
      : world_(physics::World::create(physics::profiles::arena_players()).value()) {
    physics::PlaneDef floor;
    EXPECT_TRUE(world_.add_plane(floor).ok());
    player_ = world_.create_body(player_body_def(start)).value();
  }

  void add_ramp(float slope_deg) {
    // 4 m wide along z, rising along +x from x = 2.
    const Real rise = Real(8 * std::tan(slope_deg * 3.14159265 / 180));
    physics::MeshDef ramp;
    ramp.vertices = {Vec3(2, 0, -2), Vec3(2, 0, 2), Vec3(10, rise, 2), Vec3(10, rise, -2)};
    ramp.indices = {0, 1, 2, 0, 2, 3};
    EXPECT_TRUE(world_.add_mesh(ramp).ok());
  }

  /// One tick with `input`; returns whether the player was grounded before it.
  bool tick(const PlayerInput& input) {
    const bool grounded = is_grounded(world_, player_, kRadius, config_);
    const Vec3 velocity = world_.body_state(player_).value().linear_velocity;
    EXPECT_TRUE(
        world_.set_linear_velocity(player_, move_velocity(config_, input, velocity, grounded, kDt))
            .ok());
    EXPECT_TRUE(world_.step(kDt).ok());
    return grounded;
  }
  void ticks(int count, const PlayerInput& input) {
    for (int k = 0; k < count; ++k) tick(input);
  }

  Vec3 position() const { return world_.body_state(player_).value().position; }
  Vec3 velocity() const { return world_.body_state(player_).value().linear_velocity; }
  Real horizontal_speed() const { return std::hypot(velocity().x(), velocity().z()); }
  bool grounded() const { return is_grounded(world_, player_, kRadius, config_); }
  MovementConfig& config() { return config_; }

 private:
  physics::World world_;
  physics::BodyId player_;
  MovementConfig config_;
};

PlayerInput forward(float yaw_rad = 0) {
  PlayerInput input;
  input.sequence = 1;
  input.move_forward = 1;
  input.yaw_rad = yaw_rad;
  return input;
}

PlayerInput jump() {
  PlayerInput input;
  input.buttons = proto::kButtonJump;
  return input;
}

TEST(Movement, WishDirectionFollowsTheYaw) {
  EXPECT_TRUE(wish_direction(forward(0)).isApprox(Vec3(0, 0, -1), Real(1e-6)));
  EXPECT_TRUE(wish_direction(forward(Real(3.14159265 / 2))).isApprox(Vec3(-1, 0, 0), Real(1e-6)));
  PlayerInput strafe;
  strafe.move_right = 1;
  EXPECT_TRUE(wish_direction(strafe).isApprox(Vec3(1, 0, 0), Real(1e-6)));
  EXPECT_EQ(wish_direction(PlayerInput{}), Vec3::Zero());
}

TEST(Movement, GroundAccelerationReachesTheMaxSpeed) {
  MovementWorld scene;
  scene.ticks(10, PlayerInput{});  // settle on the floor
  ASSERT_TRUE(scene.grounded());
  scene.tick(forward());
  // One tick: ground_acceleration * max_speed * dt = 10 * 7 / 60.
  EXPECT_NEAR(scene.horizontal_speed(), 10.0 * 7 / 60, 1e-3);
  scene.ticks(59, forward());
  EXPECT_NEAR(scene.horizontal_speed(), 7.0, 1e-3);
  EXPECT_LT(scene.velocity().z(), -6.99);            // yaw 0 runs along -Z
  EXPECT_NEAR(scene.position().y(), kRadius, 0.01);  // still on the floor
}

TEST(Movement, FrictionStopsAPlayerWithoutInput) {
  MovementWorld scene;
  scene.ticks(60, forward());
  ASSERT_NEAR(scene.horizontal_speed(), 7.0, 1e-3);
  scene.tick(PlayerInput{});
  // Friction takes friction * speed * dt = 10 % of 7 m/s.
  EXPECT_NEAR(scene.horizontal_speed(), 6.3, 1e-3);
  // 0.9 per tick down to the stop speed (12 ticks), then 0.2 m/s per tick (10 ticks).
  scene.ticks(21, PlayerInput{});
  EXPECT_EQ(scene.horizontal_speed(), 0);
}

TEST(Movement, AJumpReachesTheExpectedHeight) {
  MovementWorld scene;
  scene.ticks(10, PlayerInput{});
  const Real ground_y = scene.position().y();
  EXPECT_TRUE(scene.tick(jump()));
  EXPECT_NEAR(scene.velocity().y(), 5 - 9.81 * kDt, 1e-3);
  Real peak = ground_y;
  for (int k = 0; k < 60; ++k) {
    scene.tick(PlayerInput{});
    peak = std::max(peak, scene.position().y());
  }
  // v²/2g = 1.274 m, less half a step of v·dt for the discrete integration.
  EXPECT_NEAR(peak - ground_y, 25 / (2 * 9.81) - 5 * kDt / 2, 0.02);
  EXPECT_TRUE(scene.grounded());  // landed again after a 1.02 s flight
}

TEST(Movement, JumpsOnlyWhenGrounded) {
  MovementWorld scene(Vec3(0, 3, 0));
  EXPECT_FALSE(scene.grounded());
  Real previous = scene.velocity().y();
  int airborne_ticks = 0;
  while (!scene.tick(jump())) {  // holding jump all the way down
    EXPECT_LE(scene.velocity().y(), previous + 1e-6);
    previous = scene.velocity().y();
    ASSERT_LT(++airborne_ticks, 120);
  }
  EXPECT_GT(airborne_ticks, 30);                            // fell 2.6 m: about 0.73 s
  EXPECT_NEAR(scene.velocity().y(), 5 - 9.81 * kDt, 1e-3);  // and jumped on landing
}

TEST(Movement, AirControlIsWeakerThanGroundControl) {
  MovementWorld scene(Vec3(0, 100, 0));
  scene.ticks(30, forward());
  ASSERT_FALSE(scene.grounded());
  // air_acceleration * max_speed * t = 1 * 7 * 0.5 s.
  EXPECT_NEAR(scene.horizontal_speed(), 3.5, 1e-3);
  EXPECT_NEAR(scene.velocity().y(), -9.81 * 0.5, 0.01);  // gravity only
}

TEST(Movement, NoFrictionInTheAir) {
  MovementWorld scene;
  scene.ticks(60, forward());
  scene.tick(jump());
  const Real launch_speed = scene.horizontal_speed();
  scene.ticks(20, PlayerInput{});
  ASSERT_FALSE(scene.grounded());
  EXPECT_NEAR(scene.horizontal_speed(), launch_speed, 1e-4);
}

TEST(Movement, WalksUpARampAsGround) {
  MovementWorld scene(Vec3(0, kRadius, 0));
  scene.add_ramp(20);
  // Run along +x (yaw -90°) onto the ramp and up it.
  for (int k = 0; k < 90; ++k) scene.tick(forward(Real(-3.14159265 / 2)));
  EXPECT_GT(scene.position().x(), 4);
  EXPECT_GT(scene.position().y(), kRadius + 0.5);
  EXPECT_TRUE(scene.grounded());
}

/// Centre of a player touching (1 cm clear) a ramp of add_ramp(slope_deg) at height 2 m.
Vec3 beside_ramp(double slope_deg) {
  const double slope = slope_deg * 3.14159265 / 180;
  const double height = 2;
  return Vec3(Real(2 + (height * std::cos(slope) - (kRadius + 0.01)) / std::sin(slope)),
              Real(height), 0);
}

TEST(Movement, AGentleSlopeIsGroundASteepOneIsNot) {
  MovementWorld gentle(beside_ramp(20));
  gentle.add_ramp(20);
  EXPECT_TRUE(gentle.grounded());
  // Steeper than ground_max_slope_deg (50°): a wall to slide along, not ground to jump from.
  MovementWorld steep(beside_ramp(60));
  steep.add_ramp(60);
  EXPECT_FALSE(steep.grounded());
}

TEST(MovementConfig, ValidatesEveryField) {
  EXPECT_EQ(MovementConfig{}.validate(), "");
  MovementConfig config;
  config.max_speed_mps = 0;
  EXPECT_EQ(config.validate(), "movement max_speed_mps must be 0.1..100, got 0.000000");
  config = {};
  config.friction = std::nanf("");
  EXPECT_NE(config.validate().find("movement friction must be 0..1000"), std::string::npos);
  config = {};
  config.ground_max_slope_deg = 90;
  EXPECT_NE(config.validate().find("ground_max_slope_deg"), std::string::npos);
}

}  // namespace
}  // namespace ricochet::server::movement_test
