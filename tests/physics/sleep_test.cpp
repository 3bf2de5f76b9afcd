// Sleeping: a body at rest sleeps after time_to_sleep, stays exactly still while asleep, and
// wakes when something hits it or game code changes its velocity.

#include "test_util.h"

namespace ricochet::physics::test::sleep_test {
namespace {

WorldDef sleepy_def() {
  WorldDef def;  // enable_sleep = true, time_to_sleep = 0.5 s by default
  def.enable_sleep = true;
  return def;
}

/// Steps until `id` sleeps; returns the step count, or −1 if it has not within max_steps.
int steps_until_asleep(World& world, BodyId id, int max_steps) {
  for (int i = 1; i <= max_steps; ++i) {
    run_or_throw(world, 1);
    if (state_of(world, id).sleeping) return i;
  }
  return -1;
}

TEST(Sleep, RestingSphereSleepsAfterTimeToSleep) {
  World world = make_world(sleepy_def());
  add_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  const int steps = steps_until_asleep(world, ball, 120);
  ASSERT_GT(steps, 0) << "never fell asleep";
  // It is slow from the first step, so it sleeps once time_to_sleep (0.5 s, 30 steps) has passed:
  // allow a step either way for ≥ vs > and for when the timer starts, plus one for settling.
  const double t = steps * double(kDt60);
  const double tts = double(world.definition().time_to_sleep);
  EXPECT_GE(t, tts - 1.5 * double(kDt60));
  EXPECT_LE(t, tts + 2.5 * double(kDt60));

  // Asleep it does not move at all, and is not counted as awake.
  const BodyState asleep = state_of(world, ball);
  ASSERT_TRUE(run(world, 120));
  const BodyState later = state_of(world, ball);
  EXPECT_TRUE(later.sleeping);
  EXPECT_EQ(later.position, asleep.position);
  EXPECT_TRUE(later.linear_velocity.isZero());
  EXPECT_EQ(world.profile().bodies_awake, 0);
}

TEST(Sleep, NotBeforeTimeToSleep) {
  WorldDef def = sleepy_def();
  def.time_to_sleep = 2;
  World world = make_world(def);
  add_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  ASSERT_TRUE(run(world, 110));  // 1.83 s
  EXPECT_FALSE(state_of(world, ball).sleeping);
  const int more = steps_until_asleep(world, ball, 60);
  EXPECT_GT(more, 0);
}

TEST(Sleep, StackSleepsAsOneIsland) {
  World world = make_world(sleepy_def());
  add_floor(world);
  const BodyId low = add_sphere(world, Vec3(0, Real(0.5), 0));
  const BodyId high = add_sphere(world, Vec3(0, Real(1.5), 0));
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(run(world, 1));
    EXPECT_EQ(state_of(world, low).sleeping, state_of(world, high).sleeping)
        << "touching bodies sleep and wake together (step " << i << ")";
  }
  EXPECT_TRUE(state_of(world, low).sleeping);
}

TEST(Sleep, WakesWhenHit) {
  World world = make_world(sleepy_def());
  add_floor(world);
  const BodyId sleeper = add_sphere(world, Vec3(0, Real(0.5), 0));
  ASSERT_GT(steps_until_asleep(world, sleeper, 120), 0);

  // Drop a second sphere on it from 2 m above its top.
  const BodyId falling = add_sphere(world, Vec3(0, Real(3.5), 0));
  bool hit = false;
  for (int i = 0; i < 120 && !hit; ++i) {
    const double vy_before = state_of(world, falling).linear_velocity.y();
    ASSERT_TRUE(run(world, 1));
    const double vy = state_of(world, falling).linear_velocity.y();
    if (vy > vy_before + 1) {  // the impact step: a downward speed of ~6 m/s was removed
      hit = true;
      // Awake in the impact step, or at the latest in the next one (an engine may wake the
      // island when the contact is found and solve it with the sleeper one step later).
      const bool awake_now = !state_of(world, sleeper).sleeping;
      ASSERT_TRUE(run(world, 1));
      const bool awake_next = !state_of(world, sleeper).sleeping;
      EXPECT_TRUE(awake_now || awake_next) << "hit at step " << i << " but still asleep";
    }
  }
  ASSERT_TRUE(hit) << "the falling sphere never reached the sleeper";
  // It did not pass through: it rests on top of the sleeper, which is still on the floor.
  ASSERT_TRUE(run(world, 120));
  EXPECT_NEAR(state_of(world, falling).position.y(), 1.5, 0.01);
  EXPECT_NEAR(state_of(world, sleeper).position.y(), 0.5, 0.01);
  // And both fall asleep again once settled.
  ASSERT_TRUE(run(world, 120));
  EXPECT_TRUE(state_of(world, sleeper).sleeping);
  EXPECT_TRUE(state_of(world, falling).sleeping);
}

TEST(Sleep, SetLinearVelocityWakes) {
  World world = make_world(sleepy_def());
  add_floor(world, 0, material(0, 0));
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0), Real(0.5), 1, material(0, 0));
  ASSERT_GT(steps_until_asleep(world, ball, 120), 0);
  RICOCHET_ASSERT_OK(world.set_linear_velocity(ball, Vec3(1, 0, 0)));
  EXPECT_FALSE(state_of(world, ball).sleeping);
  ASSERT_TRUE(run(world, 1));
  const BodyState s = state_of(world, ball);
  EXPECT_FALSE(s.sleeping);
  EXPECT_NEAR(s.position.x(), double(kDt60), 1e-4) << "it moved at 1 m/s (frictionless)";
}

TEST(Sleep, WakeCallWakes) {
  World world = make_world(sleepy_def());
  add_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  ASSERT_GT(steps_until_asleep(world, ball, 120), 0);
  RICOCHET_ASSERT_OK(world.wake(ball));
  EXPECT_FALSE(state_of(world, ball).sleeping);
  ASSERT_TRUE(run(world, 1));
  EXPECT_FALSE(state_of(world, ball).sleeping) << "the sleep timer restarts on wake";
  // Still at rest, so it goes back to sleep after time_to_sleep.
  EXPECT_GT(steps_until_asleep(world, ball, 120), 0);
}

TEST(Sleep, SetGravityWakesEveryBody) {
  // world.h: set_gravity "wakes every body". Sideways gravity then rolls the sphere away.
  World world = make_world(sleepy_def());
  add_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  ASSERT_GT(steps_until_asleep(world, ball, 120), 0);
  RICOCHET_ASSERT_OK(world.set_gravity(Vec3(2, -kGravity, 0)));
  EXPECT_FALSE(state_of(world, ball).sleeping);
  ASSERT_TRUE(run(world, 30));
  EXPECT_GT(state_of(world, ball).position.x(), 0.1) << "rolled in the new gravity";
}

TEST(Sleep, AllowSleepFalseAndDisabledWorldNeverSleep) {
  World world = make_world(sleepy_def());
  add_floor(world);
  BodyDef insomniac = sphere_def(Vec3(0, Real(0.5), 0));
  insomniac.allow_sleep = false;
  const BodyId awake = add_body(world, insomniac);
  const BodyId normal = add_sphere(world, Vec3(3, Real(0.5), 0));
  ASSERT_TRUE(run(world, 120));
  EXPECT_FALSE(state_of(world, awake).sleeping);
  EXPECT_TRUE(state_of(world, normal).sleeping);

  World no_sleep = make_world(awake_def());
  add_floor(no_sleep);
  const BodyId ball = add_sphere(no_sleep, Vec3(0, Real(0.5), 0));
  ASSERT_TRUE(run(no_sleep, 120));
  EXPECT_FALSE(state_of(no_sleep, ball).sleeping);
}

TEST(Sleep, MovingBodyDoesNotSleep) {
  // Rolling at 1 m/s is far above sleep_linear_speed (0.05 m/s): awake for the whole 2 s.
  World world = make_world(sleepy_def());
  add_floor(world);
  BodyDef def = sphere_def(Vec3(0, Real(0.5), 0));
  def.linear_velocity = Vec3(1, 0, 0);
  def.angular_velocity = Vec3(0, 0, -2);
  const BodyId ball = add_body(world, def);
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(run(world, 1));
    ASSERT_FALSE(state_of(world, ball).sleeping) << "step " << i;
  }
}

}  // namespace
}  // namespace ricochet::physics::test::sleep_test
