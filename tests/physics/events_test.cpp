// Contact events: begin once per touch with the right normal and approach speed, impulses while
// touching, end when separated or destroyed; sensors report but neither push nor get pushed.
//
// The event lists hold the events of the last step only (the header calls them "events of the
// last step"), so the tests gather them after every step.

#include "test_util.h"

namespace ricochet::physics::test::events_test {
namespace {

struct EventLog {
  std::vector<std::pair<int, ContactBeginEvent>> begins;
  std::vector<std::pair<int, ContactEndEvent>> ends;
  std::vector<std::pair<int, ContactImpulseEvent>> impulses;

  void gather(const World& world, int step) {
    for (const auto& e : world.contact_begin_events()) begins.emplace_back(step, e);
    for (const auto& e : world.contact_end_events()) ends.emplace_back(step, e);
    for (const auto& e : world.contact_impulse_events()) impulses.emplace_back(step, e);
  }
};

bool involves(const ContactTarget& other, BodyId body, BodyId id) {
  return body == id || other.body == id;
}

TEST(Events, DropOnPlaneBeginsOnceWithNormalAndApproachSpeed) {
  World world = make_world();  // sleeping off, so impulses keep coming while it rests
  const ShapeId floor = add_floor(world, 0, material(0, Real(0.5)));
  const Real h = 2, r = Real(0.5);
  const BodyId ball = add_sphere(world, Vec3(0, h + r, 0), r, 1, material(0, Real(0.5)));
  EventLog log;
  for (int i = 0; i < 150; ++i) {  // 2.5 s: lands at t ≈ 0.64 s
    ASSERT_TRUE(run(world, 1));
    log.gather(world, i);
  }
  ASSERT_EQ(log.begins.size(), 1u) << "exactly one begin for one landing";
  const ContactBeginEvent& b = log.begins[0].second;
  EXPECT_EQ(b.body, ball);
  EXPECT_EQ(b.other.shape, floor);
  EXPECT_TRUE(b.other.body.is_null());
  EXPECT_TRUE(near(b.normal, Vec3(0, -1, 0), 1e-4)) << "normal points from the body to the floor";
  // The point lies under the ball, on the floor to within one step's travel (0.1 m).
  const double v_i = std::sqrt(2 * double(kGravity) * double(h));
  EXPECT_NEAR(b.point.x(), 0, 1e-4);
  EXPECT_NEAR(b.point.z(), 0, 1e-4);
  EXPECT_NEAR(b.point.y(), 0, v_i * double(kDt60));
  // Approach speed √(2gh) = 6.26 m/s within 2·g·dt (0.33 m/s): the touch is detected at a step
  // boundary, within one step of the exact impact, and semi-implicit Euler's speed at a given
  // height is off by up to another g·dt.
  EXPECT_GE(b.approach_speed, 0);
  EXPECT_NEAR(b.approach_speed, v_i, 2 * double(kGravity) * double(kDt60));
  EXPECT_TRUE(log.ends.empty()) << "it never left the floor (restitution 0)";

  // Resting (last second): exactly one impulse event per step for this contact, carrying the
  // weight: m·g·dt per step, within 5% (soft-contact settling).
  const int rest_from = 90;
  int rest_events = 0;
  for (const auto& [step, e] : log.impulses) {
    if (step < rest_from) continue;
    ++rest_events;
    EXPECT_EQ(e.body, ball);
    EXPECT_EQ(e.other.shape, floor);
    EXPECT_TRUE(near(e.normal, Vec3(0, -1, 0), 1e-4));
    EXPECT_NEAR(e.normal_impulse, double(kGravity) * double(kDt60),
                0.05 * double(kGravity) * double(kDt60))
        << "step " << step;
  }
  EXPECT_EQ(rest_events, 150 - rest_from);

  // Moved away: one end event, in that step only.
  RICOCHET_ASSERT_OK(world.set_transform(ball, Vec3(0, 5, 0), Quat::Identity()));
  ASSERT_TRUE(run(world, 1));
  ASSERT_EQ(world.contact_end_events().size(), 1u);
  EXPECT_EQ(world.contact_end_events()[0].body, ball);
  EXPECT_EQ(world.contact_end_events()[0].other.shape, floor);
  EXPECT_TRUE(world.contact_begin_events().empty());
  EXPECT_TRUE(world.contact_impulse_events().empty());
  ASSERT_TRUE(run(world, 1));
  EXPECT_TRUE(world.contact_end_events().empty()) << "events are per step";
}

TEST(Events, DestroyingATouchingBodyEndsItsContact) {
  World world = make_world();
  const ShapeId floor = add_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  const BodyId other = add_sphere(world, Vec3(3, Real(0.5), 0));
  ASSERT_TRUE(run(world, 10));
  RICOCHET_ASSERT_OK(world.destroy_body(ball));
  // Reported either immediately (end events of the destroy) or with the next step: not specified,
  // so both lists are gathered. Exactly one end event for the destroyed body must appear.
  std::vector<ContactEndEvent> ends(world.contact_end_events().begin(),
                                    world.contact_end_events().end());
  ASSERT_TRUE(run(world, 1));
  ends.insert(ends.end(), world.contact_end_events().begin(), world.contact_end_events().end());
  int for_ball = 0;
  for (const ContactEndEvent& e : ends) {
    if (e.body == ball) {
      ++for_ball;
      EXPECT_EQ(e.other.shape, floor);
    }
    EXPECT_FALSE(e.body == other) << "the other sphere still rests on the floor";
  }
  EXPECT_EQ(for_ball, 1);
}

TEST(Events, BodyPairBeginsOnceWithNormalTowardsTheOther) {
  World world = make_world(space_def());
  BodyDef da = sphere_def(Vec3(-1, 0, 0), Real(0.5), 1, material(0, 0));
  da.linear_velocity = Vec3(2, 0, 0);
  BodyDef db = sphere_def(Vec3(1, 0, 0), Real(0.5), 1, material(0, 0));
  db.linear_velocity = Vec3(-2, 0, 0);
  const BodyId a = add_body(world, da);
  const BodyId b = add_body(world, db);
  EventLog log;
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(run(world, 1));
    log.gather(world, i);
  }
  // One event per pair (not one per body), in either orientation.
  ASSERT_EQ(log.begins.size(), 1u);
  const ContactBeginEvent& e = log.begins[0].second;
  ASSERT_TRUE((e.body == a && e.other.body == b) || (e.body == b && e.other.body == a));
  EXPECT_TRUE(e.other.shape.is_null());
  const Vec3 towards_other = e.body == a ? Vec3(1, 0, 0) : Vec3(-1, 0, 0);
  EXPECT_TRUE(near(e.normal, towards_other, 1e-4));
  EXPECT_NEAR(e.point.x(), 0, 0.07) << "midway, to within one step's travel of either sphere";
  // No gravity: the closing speed is exactly 4 m/s (rounding only).
  EXPECT_NEAR(e.approach_speed, 4, 1e-3);
  for (const auto& [step, imp] : log.impulses) {
    EXPECT_TRUE(involves(imp.other, imp.body, a) && involves(imp.other, imp.body, b));
    EXPECT_GE(imp.normal_impulse, 0);
  }
  // e = 0, equal masses: both stop.
  EXPECT_NEAR(state_of(world, a).linear_velocity.x(), 0, 0.02);
  EXPECT_NEAR(state_of(world, b).linear_velocity.x(), 0, 0.02);
}

TEST(Events, SensorReportsButNeitherPushesNorIsPushed) {
  World world = make_world(space_def());
  BodyDef sensor_def = sphere_def(Vec3::Zero(), 1);
  sensor_def.sensor = true;
  const BodyId sensor = add_body(world, sensor_def);
  BodyDef ball_def = sphere_def(Vec3(-3, 0, 0), Real(0.25));
  ball_def.linear_velocity = Vec3(2, 0, 0);
  const BodyId ball = add_body(world, ball_def);
  EventLog log;
  for (int i = 0; i < 180; ++i) {  // 3 s: enters at t ≈ 0.9 s, leaves at t ≈ 2.1 s
    ASSERT_TRUE(run(world, 1));
    log.gather(world, i);
  }
  ASSERT_EQ(log.begins.size(), 1u);
  const ContactBeginEvent& b = log.begins[0].second;
  EXPECT_TRUE(involves(b.other, b.body, sensor) && involves(b.other, b.body, ball));
  EXPECT_NEAR(log.begins[0].first * double(kDt60), 0.875, 0.05) << "begins when the surfaces meet";
  ASSERT_EQ(log.ends.size(), 1u);
  EXPECT_TRUE(involves(log.ends[0].second.other, log.ends[0].second.body, sensor));
  EXPECT_GT(log.ends[0].first, log.begins[0].first);
  for (const auto& [step, imp] : log.impulses) {
    EXPECT_EQ(imp.normal_impulse, 0) << "a sensor contact must not be solved";
  }
  // Neither moved the other: the ball flew straight through at its speed, the sensor stayed put.
  const BodyState s = state_of(world, sensor);
  EXPECT_TRUE(s.linear_velocity.isZero());
  EXPECT_EQ(s.position, Vec3::Zero());
  EXPECT_EQ(state_of(world, ball).linear_velocity, Vec3(2, 0, 0));
  EXPECT_NEAR(state_of(world, ball).position.x(), -3 + 2 * 180 * double(kDt60), 1e-3);
}

TEST(Events, SensorFallsThroughTheFloor) {
  // Whether sensors report overlaps with static shapes is not specified (the implementation may
  // track body–body overlaps only); if it does, the event must name the sensor and the floor.
  World world = make_world();
  const ShapeId floor = add_floor(world);
  BodyDef def = sphere_def(Vec3(0, 1, 0));
  def.sensor = true;
  const BodyId sensor = add_body(world, def);
  EventLog log;
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(run(world, 1));
    log.gather(world, i);
  }
  EXPECT_LT(state_of(world, sensor).position.y(), -0.5) << "a sensor is never pushed";
  EXPECT_LE(log.begins.size(), 1u);
  for (const auto& [step, e] : log.begins) {
    EXPECT_EQ(e.body, sensor);
    EXPECT_EQ(e.other.shape, floor);
  }
  for (const auto& [step, e] : log.impulses) EXPECT_EQ(e.normal_impulse, 0);
}

TEST(Events, DisabledEventsStayEmpty) {
  WorldDef def = awake_def();
  def.contact_events = false;
  World world = make_world(def);
  add_floor(world);
  add_sphere(world, Vec3(0, 2, 0));
  for (int i = 0; i < 90; ++i) {
    ASSERT_TRUE(run(world, 1));
    EXPECT_TRUE(world.contact_begin_events().empty());
    EXPECT_TRUE(world.contact_impulse_events().empty());
    EXPECT_TRUE(world.contact_end_events().empty());
  }
}

TEST(Events, FilteredPairsProduceNothing) {
  World world = make_world();
  PlaneDef floor;
  floor.filter.layer = 2;
  floor.filter.mask = 2;
  ASSERT_TRUE(world.add_plane(floor).ok());
  const BodyId ball = add_sphere(world, Vec3(0, 1, 0));  // layer 1: not in the floor's mask
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(run(world, 1));
    EXPECT_TRUE(world.contact_begin_events().empty());
  }
  EXPECT_LT(state_of(world, ball).position.y(), -0.5) << "fell through the filtered floor";
}

}  // namespace
}  // namespace ricochet::physics::test::events_test
