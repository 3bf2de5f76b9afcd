// A step allocates nothing once the world has warmed up: every per-step buffer is reused. This
// binary replaces the global allocation functions to count calls while a step runs, so it is
// its own executable (physics_allocation_tests).

#include <execinfo.h>
#include <unistd.h>

#include <cstdlib>
#include <new>

#include "test_util.h"

namespace {

bool g_counting = false;
long g_allocations = 0;

void* allocate(std::size_t size, std::size_t alignment) {
  if (g_counting && ++g_allocations <= 3) {
    // Where a step allocated, for the failure message (resolve with addr2line -Cfe <binary>).
    void* frames[12];
    const int n = backtrace(frames, 12);
    backtrace_symbols_fd(frames, n, STDERR_FILENO);
    static constexpr char kEnd[] = "--- (an allocation inside a step)\n";
    (void)!write(STDERR_FILENO, kEnd, sizeof kEnd - 1);
  }
  if (size == 0) size = 1;
  void* p = alignment <= alignof(std::max_align_t)
                ? std::malloc(size)
                : std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
  if (!p) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t size) {
  return allocate(size, 0);
}
void* operator new[](std::size_t size) {
  return allocate(size, 0);
}
void* operator new(std::size_t size, std::align_val_t a) {
  return allocate(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return allocate(size, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}

namespace ricochet::physics::test::step_allocation_test {
namespace {

/// Allocations made by `steps` steps of `world`.
long allocations_during(World& world, int steps) {
  g_allocations = 0;
  g_counting = true;
  bool ok = true;
  for (int i = 0; i < steps; ++i) ok = ok && world.step(Real(1) / 60).ok();
  g_counting = false;
  EXPECT_TRUE(ok);
  return g_allocations;
}

/// Spheres raining into a box onto a mesh, a sensor, a kinematic pusher, contact events on;
/// projectiles fired from a gun every step (created between steps, as game code does).
struct Scene {
  World world = make_world(WorldDef{});
  BodyId shooter;
  Lcg rng{5};

  explicit Scene(const WorldDef& def) : world(make_world(def)) {
    add_closed_box(world, 4, 8, material(Real(0.4), Real(0.5)));
    add_mesh(world, {Vec3(-4, Real(0.01), -4), Vec3(4, Real(0.01), -4), Vec3(0, Real(0.01), 4)},
             {0, 1, 2});
    for (int i = 0; i < 150; ++i) {
      add_body(world, sphere_def(Vec3(rng.uniform(-3, 3), Real(1 + 0.1 * i), rng.uniform(-3, 3)),
                                 Real(0.3), 1, material(Real(0.4), Real(0.5))));
    }
    BodyDef sensor = sphere_def(Vec3(0, 1, 0), 1);
    sensor.sensor = true;
    sensor.gravity_scale = 0;
    add_body(world, sensor);
    BodyDef pusher = sphere_def(Vec3(-3, Real(0.6), 0), Real(0.5));
    pusher.type = BodyType::Kinematic;
    pusher.linear_velocity = Vec3(Real(0.5), 0, 0);
    shooter = add_body(world, pusher);
  }

  void fire() {
    ProjectileDef shot;
    shot.position = Vec3(rng.uniform(-3, 3), 6, rng.uniform(-3, 3));
    shot.velocity = Vec3(rng.uniform(-50, 50), -100, rng.uniform(-50, 50));
    shot.radius = Real(0.01);
    shot.ignore = shooter;
    (void)world.create_projectile(shot);
  }
};

TEST(StepAllocation, AWarmWorldStepsWithoutAllocating) {
  // "Warm" means the buffers have held what these steps need: the same 60 steps (restored from
  // one image, with the same shots) run once to warm up, then again counted.
  for (const bool wide : {false, true}) {
    WorldDef def;
    def.wide_simd = wide;
    def.enable_sleep = false;  // keep every phase busy
    Scene scene(def);
    for (int i = 0; i < 240; ++i) {  // the pile forms
      scene.fire();
      ASSERT_TRUE(run(scene.world, 1));
    }
    std::vector<std::uint8_t> image;
    scene.world.save_state(image, StateParts::Dynamic);
    const Lcg shots = scene.rng;
    long counted = 0;
    for (int pass = 0; pass < 2; ++pass) {
      RICOCHET_ASSERT_OK(scene.world.restore_state(image));
      scene.rng = shots;
      counted = 0;
      for (int i = 0; i < 60; ++i) {
        scene.fire();  // creating a projectile may allocate; the step must not
        counted += allocations_during(scene.world, 1);
      }
    }
    EXPECT_EQ(counted, 0) << "allocations in 60 warm steps (wide_simd " << wide << ")";
  }
}

TEST(StepAllocation, TheCounterSeesAllocations) {
  g_allocations = 0;
  g_counting = true;
  std::vector<int>* v = new std::vector<int>(100);
  g_counting = false;
  delete v;
  EXPECT_GE(g_allocations, 2);
}

}  // namespace
}  // namespace ricochet::physics::test::step_allocation_test
