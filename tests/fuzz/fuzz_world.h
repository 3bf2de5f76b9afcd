#pragma once
/// The world the restore_state fuzzer restores every input into, and the scenes its seed corpus
/// is saved from. Built from the public API only.
///
/// The fuzz world holds one of everything an image can carry: dynamic bodies (one fast, one with
/// locked rotation, one on a spring), a sensor, a kinematic body, a plane, a box, a two-triangle
/// mesh, a spring, an attractor and a projectile. Images saved from it match its configuration's
/// fingerprint, so mutated StateParts::Dynamic images reach the in-place restore.

#include <cstdint>
#include <cstdio>
#include <utility>

#include "ricochet/physics/world.h"

namespace ricochet::physics::fuzz {

inline constexpr Real kDt = Real(1) / Real(60);

/// Stops the process on a bug in the fuzz harness itself (never on a refused input).
[[noreturn]] inline void harness_bug(const char* what, const Error& error) {
  std::fprintf(stderr, "fuzz harness: %s: %s\n", what, error.message.c_str());
  __builtin_trap();
}

template <class T>
T must(Result<T> result, const char* what) {
  if (!result) harness_bug(what, result.error());
  return std::move(result).value();
}

inline void must(const Status& status, const char* what) {
  if (!status) harness_bug(what, status.error());
}

/// The server's defaults with small limits, so an image cannot ask for thousands of slots and
/// "above the limit" refusals are reachable.
inline WorldDef fuzz_world_def() {
  WorldDef def;
  def.max_bodies = 64;
  def.max_shapes = 16;
  def.max_projectiles = 16;
  return def;
}

inline BodyDef ball(const Vec3& position, Real radius) {
  BodyDef def;
  def.position = position;
  def.radius = radius;
  def.material.restitution = Real(0.3);
  def.material.friction = Real(0.5);
  def.material.rolling_resistance = Real(0.02);
  return def;
}

inline World make_fuzz_world() {
  World world = must(World::create(fuzz_world_def()), "World::create");
  must(world.add_plane(PlaneDef{}), "add_plane");
  BoxDef box;
  box.center = Vec3(2, Real(0.5), 0);
  box.half_extents = Vec3::Constant(Real(0.5));
  must(world.add_box(box), "add_box");
  MeshDef ramp;  // a slope down towards -x, at x in [-4, -1]
  ramp.vertices = {Vec3(-4, 2, -1), Vec3(-1, 0, -1), Vec3(-1, 0, 1), Vec3(-4, 2, 1)};
  ramp.indices = {0, 1, 2, 0, 2, 3};
  must(world.add_mesh(ramp), "add_mesh");

  // Falls onto the floor inside the sensor.
  must(world.create_body(ball(Vec3(0, 3, 0), Real(0.5))), "create_body falling");
  // Rests on the box.
  must(world.create_body(ball(Vec3(2, Real(1.4), 0), Real(0.4))), "create_body on box");
  BodyDef fast = ball(Vec3(-3, 4, 0), Real(0.2));
  fast.fast = true;
  fast.linear_velocity = Vec3(0, -25, 0);
  must(world.create_body(fast), "create_body fast");
  BodyDef hanging = ball(Vec3(0, Real(2.5), 3), Real(0.3));
  hanging.lock_rotation = true;
  hanging.inertia = InertiaModel::HollowSphere;
  const BodyId hanging_id = must(world.create_body(hanging), "create_body hanging");
  BodyDef sensor = ball(Vec3(0, Real(0.5), 0), 1);
  sensor.sensor = true;
  sensor.gravity_scale = 0;
  must(world.create_body(sensor), "create_body sensor");
  BodyDef kinematic = ball(Vec3(4, Real(0.5), 3), Real(0.5));
  kinematic.type = BodyType::Kinematic;
  kinematic.linear_velocity = Vec3(0, 0, Real(-0.5));
  kinematic.filter.layer = 2;
  const BodyId kinematic_id = must(world.create_body(kinematic), "create_body kinematic");

  SpringDef spring;
  spring.body = hanging_id;
  spring.anchor = Vec3(0, 4, 3);
  spring.stiffness = 20;
  spring.rest_length = 1;
  spring.damping = 4;
  must(world.add_spring(spring), "add_spring");
  AttractorDef attractor;  // pulls layer 4 only, which no body is on
  attractor.center = Vec3(0, 10, 0);
  attractor.strength = 1;
  attractor.mask = 4;
  must(world.add_attractor(attractor), "add_attractor");

  ProjectileDef bullet;
  bullet.position = Vec3(-6, 1, 3);
  bullet.velocity = Vec3(30, 0, 0);
  bullet.radius = Real(0.05);
  bullet.gravity_scale = Real(0.2);
  bullet.ignore = kinematic_id;
  bullet.user_data = 7;
  must(world.create_projectile(bullet), "create_projectile");
  return world;
}

/// Another configuration: a stack of three balls on the floor that falls asleep, a sensor
/// around its foot, and a destroyed body (a free slot in the pool).
inline World make_stack_world() {
  World world = must(World::create(fuzz_world_def()), "World::create");
  must(world.add_plane(PlaneDef{}), "add_plane");
  const BodyId gone = must(world.create_body(ball(Vec3(5, 5, 5), Real(0.5))), "create_body");
  for (int i = 0; i < 3; ++i) {
    must(world.create_body(ball(Vec3(0, Real(0.5) + Real(1.01) * Real(i), 0), Real(0.5))),
         "create_body stack");
  }
  must(world.destroy_body(gone), "destroy_body");
  BodyDef sensor = ball(Vec3(0, Real(0.3), 0), Real(0.8));
  sensor.sensor = true;
  sensor.type = BodyType::Kinematic;
  must(world.create_body(sensor), "create_body sensor");
  return world;
}

}  // namespace ricochet::physics::fuzz
