// Every input path rejects bad values with the right ErrorCode and a non-empty message, and a
// rejected call changes nothing (state hash, counts, step counter and the saved image are
// compared before and after).

#include <cctype>
#include <functional>

#include "test_util.h"

namespace ricochet::physics::test::invalid_input_test {
namespace {

/// Lower-case, spaces and dots as underscores: "Relax iterations" matches "relax_iterations".
std::string normalise(std::string text) {
  for (char& c : text) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (c == ' ' || c == '-') c = '_';
  }
  return text;
}

// ---------------------------------------------------------------------------------------------
// WorldDef

struct DefCase {
  std::string label;
  std::string field;  ///< validate() must name it
  std::function<void(WorldDef&)> mutate;
};

std::vector<DefCase> invalid_world_defs() {
  std::vector<DefCase> cases;
  auto add = [&](std::string label, std::string field, std::function<void(WorldDef&)> f) {
    cases.push_back({std::move(label), std::move(field), std::move(f)});
  };
  add("iterations 0", "iterations", [](WorldDef& d) { d.iterations = 0; });
  add("iterations -1", "iterations", [](WorldDef& d) { d.iterations = -1; });
  add("iterations 1001", "iterations", [](WorldDef& d) { d.iterations = 1001; });
  add("relax_iterations -1", "relax_iterations", [](WorldDef& d) { d.relax_iterations = -1; });
  add("relax_iterations 1001", "relax_iterations", [](WorldDef& d) { d.relax_iterations = 1001; });
  add("substeps 0", "substeps", [](WorldDef& d) { d.substeps = 0; });
  add("substeps -2", "substeps", [](WorldDef& d) { d.substeps = -2; });
  add("substeps 65", "substeps", [](WorldDef& d) { d.substeps = 65; });
  add("baumgarte -0.1", "baumgarte", [](WorldDef& d) { d.baumgarte = Real(-0.1); });
  add("baumgarte 1.5", "baumgarte", [](WorldDef& d) { d.baumgarte = Real(1.5); });
  add("baumgarte NaN", "baumgarte", [](WorldDef& d) { d.baumgarte = kNaN; });
  add("gravity NaN", "gravity", [](WorldDef& d) { d.gravity.x() = kNaN; });
  add("gravity Inf", "gravity", [](WorldDef& d) { d.gravity.y() = -kInf; });
  // Real fields without a documented range: NaN is never acceptable ("out of range or not
  // finite"), nor is a negative length, speed, time or frequency.
  const std::vector<std::pair<std::string, Real WorldDef::*>> reals = {
      {"linear_slop", &WorldDef::linear_slop},
      {"max_correction_speed", &WorldDef::max_correction_speed},
      {"contact_hertz", &WorldDef::contact_hertz},
      {"contact_damping_ratio", &WorldDef::contact_damping_ratio},
      {"restitution_threshold", &WorldDef::restitution_threshold},
      {"max_speculative_distance", &WorldDef::max_speculative_distance},
      {"max_linear_speed", &WorldDef::max_linear_speed},
      {"max_angular_speed", &WorldDef::max_angular_speed},
      {"sleep_linear_speed", &WorldDef::sleep_linear_speed},
      {"sleep_angular_speed", &WorldDef::sleep_angular_speed},
      {"time_to_sleep", &WorldDef::time_to_sleep},
  };
  for (const auto& [name, member] : reals) {
    add(cat(name, " NaN"), name, [member](WorldDef& d) { d.*member = kNaN; });
    add(cat(name, " -1"), name, [member](WorldDef& d) { d.*member = -1; });
  }
  return cases;
}

TEST(InvalidWorldDef, DefaultsAndBoundariesAreValid) {
  EXPECT_EQ(WorldDef{}.validate(), "");
  std::vector<std::function<void(WorldDef&)>> edges = {
      [](WorldDef& d) { d.iterations = 1; },         [](WorldDef& d) { d.iterations = 1000; },
      [](WorldDef& d) { d.relax_iterations = 0; },   [](WorldDef& d) { d.relax_iterations = 1000; },
      [](WorldDef& d) { d.substeps = 1; },           [](WorldDef& d) { d.substeps = 64; },
      [](WorldDef& d) { d.baumgarte = 0; },          [](WorldDef& d) { d.baumgarte = 1; },
      [](WorldDef& d) { d.gravity = Vec3::Zero(); },
  };
  for (std::size_t i = 0; i < edges.size(); ++i) {
    WorldDef def;
    edges[i](def);
    EXPECT_EQ(def.validate(), "") << "edge case " << i;
    EXPECT_TRUE(World::create(def).ok()) << "edge case " << i;
  }
}

TEST(InvalidWorldDef, EachBadFieldIsNamedAndRejected) {
  for (const DefCase& c : invalid_world_defs()) {
    WorldDef def;
    c.mutate(def);
    const std::string why = def.validate();
    EXPECT_FALSE(why.empty()) << c.label << ": validate() accepted it";
    EXPECT_NE(normalise(why).find(c.field), std::string::npos)
        << c.label << ": message does not name the field: \"" << why << "\"";
    EXPECT_TRUE(fails_with(World::create(def), ErrorCode::InvalidArgument)) << c.label;
  }
}

// ---------------------------------------------------------------------------------------------
// A populated world that rejected calls must leave alone.

struct Fixture {
  World world;
  ShapeId floor;
  BodyId a, b;
};

Fixture populated() {
  Fixture f{make_world(WorldDef{}), {}, {}, {}};
  f.floor = add_floor(f.world);
  f.a = add_sphere(f.world, Vec3(0, Real(0.5), 0));
  BodyDef moving = sphere_def(Vec3(3, 2, 0));
  moving.linear_velocity = Vec3(1, 0, 0);
  f.b = add_body(f.world, moving);
  run_or_throw(f.world, 5);
  return f;
}

// ---------------------------------------------------------------------------------------------
// BodyDef

struct BodyCase {
  std::string label;
  std::function<void(BodyDef&)> mutate;
};

TEST(InvalidBodyDef, EachBadFieldIsRejected) {
  const std::vector<BodyCase> cases = {
      {"position NaN", [](BodyDef& d) { d.position.y() = kNaN; }},
      {"position Inf", [](BodyDef& d) { d.position.x() = kInf; }},
      {"orientation NaN", [](BodyDef& d) { d.orientation.w() = kNaN; }},
      {"orientation zero", [](BodyDef& d) { d.orientation.coeffs().setZero(); }},
      {"linear_velocity NaN", [](BodyDef& d) { d.linear_velocity.z() = kNaN; }},
      {"linear_velocity Inf", [](BodyDef& d) { d.linear_velocity.x() = -kInf; }},
      {"angular_velocity NaN", [](BodyDef& d) { d.angular_velocity.x() = kNaN; }},
      {"angular_velocity Inf", [](BodyDef& d) { d.angular_velocity.y() = kInf; }},
      {"radius 0", [](BodyDef& d) { d.radius = 0; }},
      {"radius -1", [](BodyDef& d) { d.radius = -1; }},
      {"radius NaN", [](BodyDef& d) { d.radius = kNaN; }},
      {"radius Inf", [](BodyDef& d) { d.radius = kInf; }},
      {"mass 0", [](BodyDef& d) { d.mass = 0; }},
      {"mass -1", [](BodyDef& d) { d.mass = -1; }},
      {"mass NaN", [](BodyDef& d) { d.mass = kNaN; }},
      {"mass Inf", [](BodyDef& d) { d.mass = kInf; }},
      {"restitution -0.1", [](BodyDef& d) { d.material.restitution = Real(-0.1); }},
      {"restitution 1.1", [](BodyDef& d) { d.material.restitution = Real(1.1); }},
      {"restitution NaN", [](BodyDef& d) { d.material.restitution = kNaN; }},
      {"friction -0.1", [](BodyDef& d) { d.material.friction = Real(-0.1); }},
      {"friction NaN", [](BodyDef& d) { d.material.friction = kNaN; }},
      {"rolling_resistance -0.1", [](BodyDef& d) { d.material.rolling_resistance = Real(-0.1); }},
      {"rolling_resistance NaN", [](BodyDef& d) { d.material.rolling_resistance = kNaN; }},
      {"gravity_scale NaN", [](BodyDef& d) { d.gravity_scale = kNaN; }},
      {"gravity_scale Inf", [](BodyDef& d) { d.gravity_scale = kInf; }},
  };
  Fixture f = populated();
  const WorldSnapshot before = snapshot(f.world);
  for (const BodyCase& c : cases) {
    BodyDef def = sphere_def(Vec3(-3, 2, 0));
    c.mutate(def);
    EXPECT_TRUE(fails_with(f.world.create_body(def), ErrorCode::InvalidArgument)) << c.label;
    EXPECT_TRUE(unchanged(f.world, before)) << c.label;
  }
}

TEST(InvalidBodyDef, ValidEdgesAreAccepted) {
  World world = make_world();
  BodyDef kinematic = sphere_def(Vec3::Zero());
  kinematic.type = BodyType::Kinematic;
  kinematic.mass = 0;  // "ignored for kinematic bodies"
  EXPECT_TRUE(world.create_body(kinematic).ok());
  BodyDef edges = sphere_def(Vec3(3, 0, 0));
  edges.material = material(1, 0, 0);  // restitution 1 and friction 0 are in range
  edges.gravity_scale = -1;            // a finite scale of any sign is meaningful
  EXPECT_TRUE(world.create_body(edges).ok());
  BodyDef unnormalised = sphere_def(Vec3(6, 0, 0));
  unnormalised.orientation = Quat(2, 0, 0, 0);  // normalised on creation
  const BodyId id = add_body(world, unnormalised);
  EXPECT_NEAR(state_of(world, id).orientation.norm(), 1.0, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Handles

/// Every per-body call with a given id; each must fail with InvalidHandle.
std::vector<std::pair<std::string, std::function<Status(World&, BodyId)>>> body_calls() {
  return {
      {"destroy_body", [](World& w, BodyId id) { return w.destroy_body(id); }},
      {"set_transform",
       [](World& w, BodyId id) { return w.set_transform(id, Vec3(0, 3, 0), Quat::Identity()); }},
      {"set_linear_velocity",
       [](World& w, BodyId id) { return w.set_linear_velocity(id, Vec3(1, 0, 0)); }},
      {"set_angular_velocity",
       [](World& w, BodyId id) { return w.set_angular_velocity(id, Vec3(1, 0, 0)); }},
      {"apply_force", [](World& w, BodyId id) { return w.apply_force(id, Vec3(1, 0, 0)); }},
      {"apply_torque", [](World& w, BodyId id) { return w.apply_torque(id, Vec3(1, 0, 0)); }},
      {"apply_impulse",
       [](World& w, BodyId id) { return w.apply_impulse(id, Vec3(1, 0, 0), Vec3::Zero()); }},
      {"wake", [](World& w, BodyId id) { return w.wake(id); }},
  };
}

TEST(InvalidHandle, NullStaleAndOutOfRangeBodyIds) {
  Fixture f = populated();
  const BodyId stale = add_sphere(f.world, Vec3(-3, 3, 0));
  RICOCHET_ASSERT_OK(f.world.destroy_body(stale));
  // A new body may reuse the stale handle's slot; the stale handle must still not reach it.
  const BodyId reused = add_sphere(f.world, Vec3(-3, 3, 0));
  const BodyId wrong_generation{f.a.index, f.a.generation + 1};
  const std::vector<std::pair<std::string, BodyId>> bad = {
      {"null", BodyId{}},
      {"stale", stale},
      {"out of range", BodyId{1000000, 1}},
      {"wrong generation", wrong_generation},
  };
  const WorldSnapshot before = snapshot(f.world);
  for (const auto& [what, id] : bad) {
    EXPECT_FALSE(f.world.is_valid(id)) << what;
    EXPECT_TRUE(fails_with(f.world.body_state(id), ErrorCode::InvalidHandle)) << what;
    for (const auto& [call, fn] : body_calls()) {
      EXPECT_TRUE(fails_with(fn(f.world, id), ErrorCode::InvalidHandle))
          << call << " with " << what;
      EXPECT_TRUE(unchanged(f.world, before)) << call << " with " << what;
    }
  }
  EXPECT_TRUE(f.world.is_valid(reused));
  EXPECT_TRUE(f.world.is_valid(f.a));
}

TEST(InvalidHandle, ShapeIds) {
  Fixture f = populated();
  const ShapeId removed = add_box(f.world, Vec3(5, 5, 5), Vec3::Ones());
  RICOCHET_ASSERT_OK(f.world.remove_shape(removed));
  const WorldSnapshot before = snapshot(f.world);
  for (const ShapeId id :
       {ShapeId{}, removed, ShapeId{1000000, 1}, ShapeId{f.floor.index, f.floor.generation + 1}}) {
    EXPECT_TRUE(fails_with(f.world.remove_shape(id), ErrorCode::InvalidHandle))
        << id.index << "/" << id.generation;
    EXPECT_TRUE(unchanged(f.world, before));
  }
}

// ---------------------------------------------------------------------------------------------
// step(dt)

TEST(InvalidStep, NonPositiveNonFiniteAndTooLargeStepsAreRejected) {
  Fixture f = populated();
  const WorldSnapshot before = snapshot(f.world);
  for (const Real dt : {Real(0), Real(-1), -kDt60, kNaN, kInf, -kInf, Real(1.0001), Real(2)}) {
    EXPECT_TRUE(fails_with(f.world.step(dt), ErrorCode::InvalidArgument)) << "dt " << dt;
    EXPECT_TRUE(unchanged(f.world, before)) << "dt " << dt;
  }
  RICOCHET_EXPECT_OK(f.world.step(1));  // the upper bound is inclusive
  RICOCHET_EXPECT_OK(f.world.step(Real(1e-6)));
}

TEST(InvalidGravity, NonFiniteGravityIsRejected) {
  Fixture f = populated();
  const WorldSnapshot before = snapshot(f.world);
  for (const Vec3& g : {Vec3(kNaN, 0, 0), Vec3(0, -kInf, 0), Vec3(Vec3::Constant(kNaN))}) {
    EXPECT_TRUE(fails_with(f.world.set_gravity(g), ErrorCode::InvalidArgument)) << g.transpose();
    EXPECT_TRUE(unchanged(f.world, before)) << g.transpose();
    EXPECT_TRUE(f.world.definition().gravity.allFinite());
  }
}

// ---------------------------------------------------------------------------------------------
// Per-body values

TEST(InvalidBodyInput, NonFiniteValuesAreRejectedAndChangeNothing) {
  Fixture f = populated();
  RICOCHET_ASSERT_OK(f.world.apply_force(f.b, Vec3(1, 2, 3)));  // a pending force must survive
  const WorldSnapshot before = snapshot(f.world);
  const BodyState state_before = state_of(f.world, f.b);
  const Vec3 nan3 = Vec3::Constant(kNaN);
  const Vec3 inf_x(kInf, 0, 0);
  Quat zero_quat;
  zero_quat.coeffs().setZero();
  Quat nan_quat = Quat::Identity();
  nan_quat.x() = kNaN;
  const BodyId b = f.b;
  const std::vector<std::pair<std::string, std::function<Status(World&)>>> calls = {
      {"apply_force NaN", [&](World& w) { return w.apply_force(b, nan3); }},
      {"apply_force Inf", [&](World& w) { return w.apply_force(b, inf_x); }},
      {"apply_torque NaN", [&](World& w) { return w.apply_torque(b, nan3); }},
      {"apply_torque Inf", [&](World& w) { return w.apply_torque(b, inf_x); }},
      {"apply_impulse NaN", [&](World& w) { return w.apply_impulse(b, nan3, Vec3::Zero()); }},
      {"apply_impulse Inf", [&](World& w) { return w.apply_impulse(b, inf_x, Vec3::Zero()); }},
      {"apply_impulse NaN point",
       [&](World& w) { return w.apply_impulse(b, Vec3(1, 0, 0), nan3); }},
      {"set_linear_velocity NaN", [&](World& w) { return w.set_linear_velocity(b, nan3); }},
      {"set_linear_velocity Inf", [&](World& w) { return w.set_linear_velocity(b, inf_x); }},
      {"set_angular_velocity NaN", [&](World& w) { return w.set_angular_velocity(b, nan3); }},
      {"set_angular_velocity Inf", [&](World& w) { return w.set_angular_velocity(b, inf_x); }},
      {"set_transform NaN position",
       [&](World& w) { return w.set_transform(b, nan3, Quat::Identity()); }},
      {"set_transform Inf position",
       [&](World& w) { return w.set_transform(b, inf_x, Quat::Identity()); }},
      {"set_transform NaN orientation",
       [&](World& w) { return w.set_transform(b, Vec3(0, 3, 0), nan_quat); }},
      {"set_transform zero orientation",
       [&](World& w) { return w.set_transform(b, Vec3(0, 3, 0), zero_quat); }},
  };
  for (const auto& [label, call] : calls) {
    EXPECT_TRUE(fails_with(call(f.world), ErrorCode::InvalidArgument)) << label;
    EXPECT_TRUE(unchanged(f.world, before)) << label;
    const BodyState now = state_of(f.world, b);
    EXPECT_TRUE(same_state(now, state_before)) << label;
    EXPECT_EQ(now.force, state_before.force) << label;
    EXPECT_EQ(now.torque, state_before.torque) << label;
  }
}

// ---------------------------------------------------------------------------------------------
// Static shapes

TEST(InvalidShapeDef, PlanesBoxesAndMeshesAreValidated) {
  Fixture f = populated();
  const WorldSnapshot before = snapshot(f.world);
  auto expect_rejected = [&](const auto& result, const std::string& label) {
    EXPECT_TRUE(fails_with(result, ErrorCode::InvalidArgument)) << label;
    EXPECT_TRUE(unchanged(f.world, before)) << label;
  };

  auto plane = [](std::function<void(PlaneDef&)> mutate) {
    PlaneDef def;
    mutate(def);
    return def;
  };
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.normal = Vec3::Zero(); })),
                  "plane zero normal");
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.normal.x() = kNaN; })),
                  "plane NaN normal");
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.normal.y() = kInf; })),
                  "plane Inf normal");
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.offset = kNaN; })),
                  "plane NaN offset");
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.offset = kInf; })),
                  "plane Inf offset");
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.material.restitution = 2; })),
                  "plane restitution 2");
  expect_rejected(f.world.add_plane(plane([](PlaneDef& d) { d.material.friction = -1; })),
                  "plane friction -1");

  auto box = [](std::function<void(BoxDef&)> mutate) {
    BoxDef def;
    def.center = Vec3(10, 0, 0);
    mutate(def);
    return def;
  };
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.half_extents = Vec3(0, 1, 1); })),
                  "box zero half extent");
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.half_extents = Vec3(1, -1, 1); })),
                  "box negative half extent");
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.half_extents = Vec3(1, 1, kNaN); })),
                  "box NaN half extent");
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.center.x() = kNaN; })), "box NaN center");
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.orientation.w() = kNaN; })),
                  "box NaN orientation");
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.orientation.coeffs().setZero(); })),
                  "box zero orientation");
  expect_rejected(f.world.add_box(box([](BoxDef& d) { d.material.restitution = Real(-0.5); })),
                  "box restitution -0.5");

  auto mesh = [](std::vector<std::uint32_t> indices, Vec3 third = Vec3(0, 0, 1)) {
    MeshDef def;
    def.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), third};
    def.indices = std::move(indices);
    return def;
  };
  expect_rejected(f.world.add_mesh(mesh({0, 1, 3})), "mesh index out of range");
  expect_rejected(f.world.add_mesh(mesh({0, 1, 2, 0})), "mesh 4 indices");
  expect_rejected(f.world.add_mesh(mesh({0, 1})), "mesh 2 indices");
  expect_rejected(f.world.add_mesh(mesh({0, 1, 2}, Vec3(0, kNaN, 1))), "mesh NaN vertex");
  expect_rejected(f.world.add_mesh(mesh({0, 1, 2}, Vec3(0, 0, kInf))), "mesh Inf vertex");
  expect_rejected(f.world.add_mesh(mesh({0, 1, 0xFFFFFFFFu})), "mesh index 2^32-1");

  // The same definitions with the defect removed are accepted.
  EXPECT_TRUE(f.world.add_plane(plane([](PlaneDef&) {})).ok());
  EXPECT_TRUE(f.world.add_box(box([](BoxDef&) {})).ok());
  EXPECT_TRUE(f.world.add_mesh(mesh({0, 1, 2})).ok());
}

// ---------------------------------------------------------------------------------------------
// Capacity

TEST(Capacity, BodiesAndShapesBeyondTheLimitAreRejected) {
  WorldDef def;
  def.max_bodies = 2;
  def.max_shapes = 1;
  World world = make_world(def);
  add_floor(world);
  add_sphere(world, Vec3(0, 1, 0));
  add_sphere(world, Vec3(2, 1, 0));
  const WorldSnapshot before = snapshot(world);
  EXPECT_TRUE(
      fails_with(world.create_body(sphere_def(Vec3(4, 1, 0))), ErrorCode::CapacityExceeded));
  EXPECT_TRUE(fails_with(world.add_box(BoxDef{}), ErrorCode::CapacityExceeded));
  EXPECT_TRUE(unchanged(world, before));
}

TEST(Capacity, DestroyingFreesCapacity) {
  WorldDef def;
  def.max_bodies = 1;
  World world = make_world(def);
  const BodyId first = add_sphere(world, Vec3(0, 1, 0));
  EXPECT_TRUE(
      fails_with(world.create_body(sphere_def(Vec3(2, 1, 0))), ErrorCode::CapacityExceeded));
  RICOCHET_ASSERT_OK(world.destroy_body(first));
  EXPECT_TRUE(world.create_body(sphere_def(Vec3(2, 1, 0))).ok());
}

}  // namespace
}  // namespace ricochet::physics::test::invalid_input_test
