// The "Physics in five lines" example of physics/README.md, verbatim, so it stays true.
#include <gtest/gtest.h>

#include "ricochet/physics/world.h"

namespace rp = ricochet::physics;

TEST(ReadmeExample, BallFallsOntoThePlaneAndRests) {
  rp::World world = rp::World::create(rp::WorldDef{}).value();  // gravity -9.81 m/s², 10 iterations
  (void)world.add_plane({.normal = rp::Vec3::UnitY(), .offset = 0});
  rp::BodyId ball = world.create_body({.position = {0, 5, 0}, .radius = 0.5f, .mass = 1}).value();
  for (int i = 0; i < 120; ++i) (void)world.step(1.0f / 60);  // time is a parameter
  rp::Vec3 where = world.body_state(ball).value().position;

  // Dropped from 5 m, a 0.5 m ball touches the floor after sqrt(2·4.5/9.81) ≈ 0.96 s and, with
  // the default restitution 0, rests with its centre at its radius by 2 s (within the 5 mm slop).
  EXPECT_NEAR(where.y(), 0.5, 0.006);
}
