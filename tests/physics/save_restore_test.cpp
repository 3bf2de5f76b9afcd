// save_state / restore_state: rollback is bit-exact, and bad bytes are rejected without touching
// the world.

#include "test_util.h"

namespace ricochet::physics::test::save_restore_test {
namespace {

/// A box of planes plus a static box and a mesh ramp, spheres falling into it; sleeping on.
World build_scene(int count, std::vector<BodyId>& ids) {
  World world = make_world(WorldDef{});
  add_closed_box(world, 3, 10, material(Real(0.3), Real(0.5)));
  add_box(world, Vec3(1, Real(0.5), 1), Vec3(Real(0.5), Real(0.5), Real(0.5)));
  add_mesh(world, {Vec3(-3, 0, -3), Vec3(0, 0, -3), Vec3(-3, 2, 0)}, {0, 1, 2});
  Lcg rng(7);
  for (int i = 0; i < count; ++i) {
    BodyDef def =
        sphere_def(Vec3(rng.uniform(-2.5, 2.5), Real(1.5 + 0.9 * i), rng.uniform(-2.5, 2.5)),
                   Real(0.35), rng.uniform(0.5, 2), material(Real(0.3), Real(0.5)));
    def.linear_velocity = Vec3(rng.uniform(-3, 3), 0, rng.uniform(-3, 3));
    ids.push_back(add_body(world, def));
  }
  return world;
}

TEST(SaveRestore, RoundTripReplaysBitExactly) {
  std::vector<BodyId> ids;
  World world = build_scene(50, ids);
  ASSERT_TRUE(run(world, 100));
  const std::uint64_t hash_at_save = world.state_hash();
  std::vector<BodyState> states_at_save;
  for (BodyId id : ids) states_at_save.push_back(state_of(world, id));
  const std::vector<std::uint8_t> image = world.save_state();
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(world.state_hash(), hash_at_save) << "save_state changed the world";

  ASSERT_TRUE(run(world, 100));
  const std::uint64_t hash_at_200 = world.state_hash();
  ASSERT_NE(hash_at_200, hash_at_save);

  RICOCHET_ASSERT_OK(world.restore_state(image));
  EXPECT_EQ(world.step_count(), 100u);
  EXPECT_EQ(world.state_hash(), hash_at_save);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    ASSERT_TRUE(world.is_valid(ids[k])) << "body " << k;
    EXPECT_TRUE(same_state(state_of(world, ids[k]), states_at_save[k])) << "body " << k;
  }
  ASSERT_TRUE(run(world, 100));
  EXPECT_EQ(world.state_hash(), hash_at_200) << "replay after restore diverged";

  // Restoring twice in a row, and saving right after a restore, give the same image.
  RICOCHET_ASSERT_OK(world.restore_state(image));
  RICOCHET_ASSERT_OK(world.restore_state(image));
  EXPECT_EQ(world.save_state(), image);
}

TEST(SaveRestore, RestoreIntoAFreshWorld) {
  // The image holds the whole world (bodies, shapes, contact cache, sleep state), so a fresh world
  // with the same definition continues exactly like the original.
  std::vector<BodyId> ids;
  World original = build_scene(30, ids);
  ASSERT_TRUE(run(original, 60));
  const std::vector<std::uint8_t> image = original.save_state();
  ASSERT_TRUE(run(original, 60));

  World copy = make_world(WorldDef{});
  RICOCHET_ASSERT_OK(copy.restore_state(image));
  EXPECT_EQ(copy.body_count(), original.body_count());
  EXPECT_EQ(copy.shape_count(), original.shape_count());
  ASSERT_TRUE(run(copy, 60));
  EXPECT_EQ(copy.state_hash(), original.state_hash());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    EXPECT_TRUE(same_state(state_of(copy, ids[k]), state_of(original, ids[k]))) << "body " << k;
  }
}

TEST(SaveRestore, BodiesCreatedAfterTheSaveAreGoneAndDestroyedOnesReturn) {
  std::vector<BodyId> ids;
  World world = build_scene(10, ids);
  ASSERT_TRUE(run(world, 20));
  const std::vector<std::uint8_t> image = world.save_state();
  const std::uint32_t count = world.body_count();
  RICOCHET_ASSERT_OK(world.destroy_body(ids[3]));
  const BodyId later = add_sphere(world, Vec3(0, 5, 0));
  ASSERT_TRUE(run(world, 20));

  RICOCHET_ASSERT_OK(world.restore_state(image));
  EXPECT_EQ(world.body_count(), count);
  EXPECT_TRUE(world.is_valid(ids[3]));
  EXPECT_FALSE(world.is_valid(later));
  EXPECT_TRUE(fails_with(world.body_state(later), ErrorCode::InvalidHandle));
}

/// A small world whose image is short enough to try every truncation.
World small_world(std::vector<BodyId>& ids) {
  World world = make_world(WorldDef{});
  add_floor(world);
  add_box(world, Vec3(2, 0, 0), Vec3::Constant(Real(0.5)));
  add_mesh(world, {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1)}, {0, 1, 2});
  ids.push_back(add_sphere(world, Vec3(0, 1, 0)));
  ids.push_back(add_sphere(world, Vec3(Real(0.2), 2, 0)));
  ids.push_back(add_sphere(world, Vec3(2, Real(1.6), 0), Real(0.3)));
  // Two projectiles, one destroyed, so the image carries a live slot and a free one.
  ProjectileDef drifting;
  drifting.position = Vec3(-3, 5, 0);
  drifting.velocity = Vec3(1, 0, 0);
  drifting.gravity_scale = 0;
  drifting.radius = Real(0.01);
  unwrap(world.create_projectile(drifting), "create_projectile");
  const ProjectileId gone = unwrap(world.create_projectile(drifting), "create_projectile");
  RICOCHET_EXPECT_OK(world.destroy_projectile(gone));
  return world;
}

TEST(SaveRestore, EveryTruncationIsRejectedAndLeavesTheWorldUnchanged) {
  std::vector<BodyId> ids;
  World source = small_world(ids);
  ASSERT_TRUE(run(source, 30));
  const std::vector<std::uint8_t> image = source.save_state();
  ASSERT_GT(image.size(), 8u);

  // The target is a different state of the same scene, so a partial restore would show.
  std::vector<BodyId> target_ids;
  World target = small_world(target_ids);
  ASSERT_TRUE(run(target, 5));
  const WorldSnapshot before = snapshot(target);
  int failures = 0;
  for (std::size_t length = 0; length < image.size(); ++length) {
    const Status status = target.restore_state(std::span(image.data(), length));
    const ::testing::AssertionResult code = fails_with(status, ErrorCode::CorruptState);
    const ::testing::AssertionResult same = unchanged(target, before);
    if (!code || !same) {
      if (++failures <= 5) {
        ADD_FAILURE() << "truncated to " << length << " of " << image.size()
                      << " bytes: " << (code ? "" : code.message()) << " "
                      << (same ? "" : same.message());
      }
    }
  }
  EXPECT_EQ(failures, 0);
  // The full image still restores afterwards.
  RICOCHET_ASSERT_OK(target.restore_state(image));
  EXPECT_EQ(target.state_hash(), source.state_hash());
}

TEST(SaveRestore, GarbageIsRejectedAndLeavesTheWorldUnchanged) {
  std::vector<BodyId> ids;
  World world = small_world(ids);
  ASSERT_TRUE(run(world, 30));
  const std::vector<std::uint8_t> image = world.save_state();
  ASSERT_TRUE(run(world, 10));
  const WorldSnapshot before = snapshot(world);

  std::vector<std::vector<std::uint8_t>> bad;
  Lcg rng(31337);
  for (std::size_t size :
       {std::size_t(1), std::size_t(16), std::size_t(100), image.size(), image.size() * 2}) {
    std::vector<std::uint8_t> bytes(size);
    for (auto& b : bytes) b = rng.byte();
    bad.push_back(std::move(bytes));
  }
  bad.push_back(std::vector<std::uint8_t>(image.size(), 0));     // all zero
  bad.push_back(std::vector<std::uint8_t>(image.size(), 0xFF));  // all ones (NaN patterns)
  {
    std::vector<std::uint8_t> trailing = image;  // valid image plus one stray byte
    trailing.push_back(0);
    bad.push_back(std::move(trailing));
  }
  {
    std::vector<std::uint8_t> header = image;  // first bytes (magic/version) damaged
    for (std::size_t i = 0; i < 4 && i < header.size(); ++i) header[i] ^= 0x5A;
    bad.push_back(std::move(header));
  }
  for (std::size_t k = 0; k < bad.size(); ++k) {
    EXPECT_TRUE(fails_with(world.restore_state(bad[k]), ErrorCode::CorruptState))
        << "bad image #" << k << " (" << bad[k].size() << " bytes)";
    EXPECT_TRUE(unchanged(world, before)) << "bad image #" << k;
  }
}

}  // namespace
}  // namespace ricochet::physics::test::save_restore_test
