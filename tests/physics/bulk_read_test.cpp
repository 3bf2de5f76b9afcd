// What a server reads each tick: live body ids, many bodies' state in one call, and the bodies that
// moved, woke or fell asleep in the last step (body move events).

#include <array>

#include "test_util.h"

namespace ricochet::physics::test::bulk_read_test {
namespace {

BodyDef tagged(const Vec3& position, std::uint64_t user_data) {
  BodyDef def = sphere_def(position);
  def.user_data = user_data;
  return def;
}

const BodyMoveEvent* move_of(const World& world, BodyId id) {
  for (const BodyMoveEvent& e : world.body_move_events()) {
    if (e.body == id) return &e;
  }
  return nullptr;
}

TEST(LiveBodies, SlotOrderSkippingDestroyedAndCountingAll) {
  World world = make_world(space_def());
  std::vector<BodyId> made;
  for (int i = 0; i < 5; ++i) made.push_back(add_sphere(world, Vec3(Real(2 * i), 0, 0)));
  RICOCHET_ASSERT_OK(world.destroy_body(made[1]));
  RICOCHET_ASSERT_OK(world.destroy_body(made[3]));

  std::vector<BodyId> ids(8);
  const std::uint32_t live = world.live_bodies(ids);
  ASSERT_EQ(live, 3u);
  EXPECT_EQ(ids[0], made[0]);
  EXPECT_EQ(ids[1], made[2]);
  EXPECT_EQ(ids[2], made[4]);

  // A short span gets the first ones and still learns how many there are.
  std::array<BodyId, 2> two{};
  EXPECT_EQ(world.live_bodies(two), 3u);
  EXPECT_EQ(two[0], made[0]);
  EXPECT_EQ(two[1], made[2]);
  EXPECT_EQ(world.live_bodies({}), 3u);
}

TEST(ReadBodies, MatchesBodyStateFieldByField) {
  World world = make_world(awake_def());
  add_floor(world);
  std::vector<BodyId> ids;
  for (int i = 0; i < 4; ++i) {
    BodyDef def = tagged(Vec3(Real(3 * i), Real(2 + i), 0), 100 + static_cast<std::uint64_t>(i));
    def.linear_velocity = Vec3(1, 0, Real(-i));
    def.angular_velocity = Vec3(0, Real(i), 1);
    ids.push_back(add_body(world, def));
  }
  ASSERT_TRUE(run(world, 20));
  // Ask in an order of the caller's own, with a repeat.
  const std::vector<BodyId> asked = {ids[2], ids[0], ids[3], ids[2]};
  std::vector<Vec3> p(4), v(4), w(4);
  std::vector<Quat> q(4);
  std::vector<std::uint64_t> user(4);
  RICOCHET_ASSERT_OK(world.read_bodies(asked, {.positions = p,
                                               .orientations = q,
                                               .linear_velocities = v,
                                               .angular_velocities = w,
                                               .user_data = user}));
  for (std::size_t i = 0; i < asked.size(); ++i) {
    const BodyState s = state_of(world, asked[i]);
    EXPECT_TRUE((p[i].array() == s.position.array()).all()) << i;
    EXPECT_TRUE((q[i].coeffs().array() == s.orientation.coeffs().array()).all()) << i;
    EXPECT_TRUE((v[i].array() == s.linear_velocity.array()).all()) << i;
    EXPECT_TRUE((w[i].array() == s.angular_velocity.array()).all()) << i;
    EXPECT_EQ(user[i], s.user_data) << i;
  }
  EXPECT_EQ(user[0], 102u);
  EXPECT_EQ(user[1], 100u);
}

TEST(ReadBodies, EmptySpansAreLeftOut) {
  World world = make_world(space_def());
  const BodyId a = add_body(world, tagged(Vec3(1, 2, 3), 7));
  std::array<Vec3, 1> p{Vec3::Zero()};
  RICOCHET_ASSERT_OK(world.read_bodies(std::array{a}, {.positions = p}));
  EXPECT_TRUE(near(p[0], Vec3(1, 2, 3), 0));
  RICOCHET_EXPECT_OK(world.read_bodies(std::array{a}, {}));
  RICOCHET_EXPECT_OK(world.read_bodies({}, {}));
}

TEST(ReadBodies, SizeMismatchIsRejectedAndNothingWritten) {
  World world = make_world(space_def());
  const BodyId a = add_sphere(world, Vec3(1, 0, 0));
  const BodyId b = add_sphere(world, Vec3(2, 0, 0));
  std::vector<Vec3> p(2, Vec3::Constant(-9));
  std::vector<Vec3> v(3, Vec3::Constant(-9));
  const Status s = world.read_bodies(std::array{a, b}, {.positions = p, .linear_velocities = v});
  ASSERT_TRUE(fails_with(s, ErrorCode::InvalidArgument));
  EXPECT_NE(s.error().message.find("linear_velocities"), std::string::npos) << s.error().message;
  EXPECT_NE(s.error().message.find("3"), std::string::npos) << s.error().message;
  EXPECT_TRUE(near(p[0], Vec3::Constant(-9), 0)) << "written despite the error";
}

TEST(ReadBodies, StaleIdIsInvalidHandleNamingItsIndex) {
  World world = make_world(space_def());
  const BodyId a = add_sphere(world, Vec3(1, 0, 0));
  const BodyId b = add_sphere(world, Vec3(2, 0, 0));
  const BodyId c = add_sphere(world, Vec3(3, 0, 0));
  RICOCHET_ASSERT_OK(world.destroy_body(c));
  std::vector<Vec3> p(3, Vec3::Constant(-9));
  const Status s = world.read_bodies(std::array{a, b, c}, {.positions = p});
  ASSERT_TRUE(fails_with(s, ErrorCode::InvalidHandle));
  EXPECT_NE(s.error().message.find("ids[2]"), std::string::npos) << s.error().message;
  EXPECT_TRUE(near(p[0], Vec3::Constant(-9), 0)) << "written despite the error";
  EXPECT_TRUE(fails_with(world.read_bodies(std::array{BodyId{}}, {}), ErrorCode::InvalidHandle));
}

TEST(BodyMoveEvents, FallingBodyReportsItsNewTransformEachStep) {
  World world = make_world(awake_def());
  const BodyId ball = add_body(world, tagged(Vec3(0, 10, 0), 42));
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(run(world, 1));
    ASSERT_EQ(world.body_move_events().size(), 1u);
    const BodyMoveEvent& e = world.body_move_events()[0];
    const BodyState s = state_of(world, ball);
    EXPECT_EQ(e.body, ball);
    EXPECT_EQ(e.user_data, 42u);
    EXPECT_TRUE(near(e.position, s.position, 0));
    EXPECT_TRUE((e.orientation.coeffs().array() == s.orientation.coeffs().array()).all());
    EXPECT_FALSE(e.fell_asleep);
    EXPECT_FALSE(e.woke);
  }
}

TEST(BodyMoveEvents, BodiesAtRestReportNothingUntilMoved) {
  World world = make_world(space_def());
  const BodyId still = add_sphere(world, Vec3(0, 0, 0));
  BodyDef def = sphere_def(Vec3(5, 0, 0));
  def.type = BodyType::Kinematic;
  const BodyId platform = add_body(world, def);
  // Created since the last step: reported once, then nothing while nothing moves.
  ASSERT_TRUE(run(world, 1));
  EXPECT_NE(move_of(world, still), nullptr);
  EXPECT_NE(move_of(world, platform), nullptr);
  ASSERT_TRUE(run(world, 3));
  EXPECT_TRUE(world.body_move_events().empty());

  // Moved by game code between steps: reported with the new place even though it does not move
  // during the step.
  RICOCHET_ASSERT_OK(world.set_transform(platform, Vec3(7, 1, 0), Quat::Identity()));
  ASSERT_TRUE(run(world, 1));
  ASSERT_EQ(world.body_move_events().size(), 1u);
  EXPECT_EQ(world.body_move_events()[0].body, platform);
  EXPECT_TRUE(near(world.body_move_events()[0].position, Vec3(7, 1, 0), 0));
  ASSERT_TRUE(run(world, 1));
  EXPECT_TRUE(world.body_move_events().empty());

  RICOCHET_ASSERT_OK(world.set_linear_velocity(still, Vec3(1, 0, 0)));
  ASSERT_TRUE(run(world, 1));
  ASSERT_EQ(world.body_move_events().size(), 1u);
  EXPECT_EQ(world.body_move_events()[0].body, still);

  RICOCHET_ASSERT_OK(world.destroy_body(still));
  ASSERT_TRUE(run(world, 1));
  EXPECT_TRUE(world.body_move_events().empty());
}

/// A world with sleeping on and a ball resting on the floor.
World resting_ball_world(BodyId& ball) {
  WorldDef def;
  def.enable_sleep = true;
  World world = make_world(def);
  add_floor(world);
  ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  return world;
}

TEST(BodyMoveEvents, FellAsleepOnceThenSilentThenWoke) {
  BodyId ball;
  World world = resting_ball_world(ball);
  int asleep_events = 0, steps = 0;
  for (; steps < 200 && !state_of(world, ball).sleeping; ++steps) {
    ASSERT_TRUE(run(world, 1));
    const BodyMoveEvent* e = move_of(world, ball);
    if (e != nullptr && e->fell_asleep) ++asleep_events;
  }
  ASSERT_TRUE(state_of(world, ball).sleeping) << "never fell asleep";
  EXPECT_EQ(asleep_events, 1);
  ASSERT_TRUE(run(world, 10));
  EXPECT_TRUE(world.body_move_events().empty()) << "a sleeping body reported a move";

  RICOCHET_ASSERT_OK(world.wake(ball));
  ASSERT_TRUE(run(world, 1));
  const BodyMoveEvent* e = move_of(world, ball);
  ASSERT_NE(e, nullptr);
  EXPECT_TRUE(e->woke);
  EXPECT_FALSE(e->fell_asleep);
  ASSERT_TRUE(run(world, 1));
  e = move_of(world, ball);
  EXPECT_TRUE(e == nullptr || !e->woke) << "woke reported twice";
}

TEST(BodyMoveEvents, ReusedSlotStartsFresh) {
  BodyId ball;
  World world = resting_ball_world(ball);
  for (int i = 0; i < 200 && !state_of(world, ball).sleeping; ++i) ASSERT_TRUE(run(world, 1));
  ASSERT_TRUE(state_of(world, ball).sleeping);
  RICOCHET_ASSERT_OK(world.wake(ball));  // marks it woken, then it is gone
  RICOCHET_ASSERT_OK(world.destroy_body(ball));
  const BodyId fresh = add_sphere(world, Vec3(3, 2, 0));
  ASSERT_EQ(fresh.index, ball.index) << "test assumes the slot is reused";
  ASSERT_TRUE(run(world, 1));
  const BodyMoveEvent* e = move_of(world, fresh);
  ASSERT_NE(e, nullptr);
  EXPECT_FALSE(e->woke) << "the new body inherited the old one's wake";
}

}  // namespace
}  // namespace ricochet::physics::test::bulk_read_test
