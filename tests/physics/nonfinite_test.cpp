// Non-finite containment: a huge but finite force on one body must not put NaN or Inf into any
// other body. If the pushed body's own state overflows, it is restored to its state before the
// step, frozen, and named by a NonFiniteEvent (events.h); otherwise it stays finite.

#include "test_util.h"

namespace ricochet::physics::test::nonfinite_test {
namespace {

struct Crowd {
  World world;
  BodyId victim;
  std::vector<BodyId> neighbours;
};

/// The victim in the middle of four touching neighbours on a floor, a fifth one on top.
Crowd make_crowd(Real victim_mass) {
  Crowd c{make_world(), {}, {}};
  add_floor(c.world);
  c.victim = add_sphere(c.world, Vec3(0, Real(0.5), 0), Real(0.5), victim_mass);
  for (const Vec3& p : {Vec3(1, Real(0.5), 0), Vec3(-1, Real(0.5), 0), Vec3(0, Real(0.5), 1),
                        Vec3(0, Real(0.5), -1), Vec3(0, Real(1.5), 0)}) {
    c.neighbours.push_back(add_sphere(c.world, p));
  }
  run_or_throw(c.world, 5);
  return c;
}

struct Containment {
  bool victim_frozen = false;
  int events_for_victim = 0;
};

/// Steps after a single huge push and checks the promises at every step.
Containment push_and_watch(Crowd& c, const Vec3& force, int steps) {
  Containment result;
  const Status applied = c.world.apply_force(c.victim, force);
  EXPECT_TRUE(applied.ok()) << "a finite force is valid input: "
                            << (applied.ok() ? "" : applied.error().message);
  for (int i = 0; i < steps; ++i) {
    const BodyState before = state_of(c.world, c.victim);
    run_or_throw(c.world, 1);
    const BodyState after = state_of(c.world, c.victim);

    for (const NonFiniteEvent& e : c.world.nonfinite_events()) {
      EXPECT_EQ(e.body, c.victim) << "step " << i << ": only the pushed body may overflow";
      if (e.body == c.victim) ++result.events_for_victim;
    }
    for (std::size_t k = 0; k < c.neighbours.size(); ++k) {
      const BodyState n = state_of(c.world, c.neighbours[k]);
      EXPECT_TRUE(is_finite(n)) << "NaN/Inf leaked into neighbour " << k << " at step " << i;
      EXPECT_FALSE(n.frozen) << "neighbour " << k << " frozen at step " << i;
    }
    // The victim is either finite and free, or frozen at its pre-step state with an event.
    EXPECT_TRUE(is_finite(after)) << "step " << i << ": a non-finite state must not be visible";
    if (after.frozen && !before.frozen) {
      result.victim_frozen = true;
      EXPECT_EQ(after.position, before.position) << "restored to its position before the step";
      EXPECT_EQ(after.linear_velocity, Vec3::Zero()) << "and stopped";
      bool named = false;
      for (const NonFiniteEvent& e : c.world.nonfinite_events())
        named = named || e.body == c.victim;
      EXPECT_TRUE(named) << "frozen at step " << i << " without a NonFiniteEvent";
    }
    if (before.frozen) {
      EXPECT_TRUE(after.frozen) << "a frozen body stays frozen";
      EXPECT_EQ(after.position, before.position) << "a frozen body does not move";
    }
  }
  return result;
}

TEST(NonFinite, HugeForceOnOneBodyDoesNotLeakIntoOthers) {
  // 1e38 N on 1 kg: a = 1e38 m/s² and v = a·dt ≈ 1.7e36 m/s are still finite in float, but
  // squaring that velocity or multiplying it by an effective mass overflows. The engine may clamp
  // it to max_linear_speed or freeze the body; either way the neighbours must stay clean.
  Crowd c = make_crowd(1);
  const Containment r = push_and_watch(c, Vec3(Real(1e38), 0, 0), 30);
  if (r.victim_frozen) {
    EXPECT_GE(r.events_for_victim, 1);
  }
}

TEST(NonFinite, OverflowingAccelerationFreezesAndReportsTheBody) {
  // 1e38 N on 1 g overflows float (a = 1e41 m/s²); in double it stays finite and is clamped to
  // max_linear_speed instead. Either outcome must satisfy the containment promises.
  Crowd c = make_crowd(Real(1e-3));
  const Containment r = push_and_watch(c, Vec3(Real(1e38), Real(-1e38), Real(1e38)), 30);
  if (r.victim_frozen) {
    EXPECT_EQ(r.events_for_victim, 1) << "one event when it freezes, not one per step";
  } else {
    // Not frozen: then it must have been clamped to the speed limit.
    const BodyState s = state_of(c.world, c.victim);
    EXPECT_LE(s.linear_velocity.norm(), c.world.definition().max_linear_speed * Real(1.0001));
  }
}

TEST(NonFinite, HugeTorqueIsClampedOrContained) {
  Crowd c = make_crowd(1);
  RICOCHET_ASSERT_OK(c.world.apply_torque(c.victim, Vec3(0, Real(1e38), 0)));
  ASSERT_TRUE(run(c.world, 10));
  const BodyState s = state_of(c.world, c.victim);
  EXPECT_TRUE(is_finite(s));
  if (!s.frozen) {
    EXPECT_LE(s.angular_velocity.norm(), c.world.definition().max_angular_speed * Real(1.0001));
  }
  for (BodyId n : c.neighbours) EXPECT_TRUE(is_finite(state_of(c.world, n)));
}

TEST(NonFinite, WorldKeepsSteppingAndHashingAfterAFreeze) {
  Crowd c = make_crowd(Real(1e-3));
  RICOCHET_ASSERT_OK(c.world.apply_force(c.victim, Vec3::Constant(Real(1e38))));
  ASSERT_TRUE(run(c.world, 60));
  // The world is still usable: hashing, saving and restoring work.
  const std::uint64_t hash = c.world.state_hash();
  const std::vector<std::uint8_t> image = c.world.save_state();
  ASSERT_TRUE(run(c.world, 10));
  RICOCHET_ASSERT_OK(c.world.restore_state(image));
  EXPECT_EQ(c.world.state_hash(), hash);
  for (BodyId n : c.neighbours) EXPECT_TRUE(is_finite(state_of(c.world, n)));
}

}  // namespace
}  // namespace ricochet::physics::test::nonfinite_test
