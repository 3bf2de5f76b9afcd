/// World API: validation of every input, body and shape lifetime, and the step's table of contents.

#include "ricochet/physics/world.h"

#include <algorithm>
#include <cmath>

#include "math_util.h"
#include "profile_timer.h"
#include "show.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

Error invalid(const std::string& message) {
  return Error{ErrorCode::InvalidArgument, message};
}
Error bad_handle(const char* what) {
  return Error{ErrorCode::InvalidHandle, std::string(what) + ": null, stale or unknown BodyId"};
}

std::string validate_material(const Material& m) {
  if (!std::isfinite(m.restitution) || m.restitution < 0 || m.restitution > 1) {
    return "material.restitution must be 0..1, got " + show(m.restitution);
  }
  if (!std::isfinite(m.friction) || m.friction < 0)
    return "material.friction must be >= 0, got " + show(m.friction);
  if (!std::isfinite(m.rolling_resistance) || m.rolling_resistance < 0) {
    return "material.rolling_resistance must be >= 0, got " + show(m.rolling_resistance);
  }
  return {};
}

std::string validate_body(const BodyDef& d) {
  if (!is_finite(d.position)) return "position must be finite, got " + show(d.position);
  if (!is_finite(d.orientation) || d.orientation.squaredNorm() < Real(1e-12)) {
    return "orientation must be a finite, non-zero quaternion";
  }
  if (!is_finite(d.linear_velocity))
    return "linear_velocity must be finite, got " + show(d.linear_velocity);
  if (!is_finite(d.angular_velocity))
    return "angular_velocity must be finite, got " + show(d.angular_velocity);
  if (!std::isfinite(d.radius) || d.radius <= 0)
    return "radius must be > 0 m, got " + show(d.radius);
  if (d.type == BodyType::Dynamic && (!std::isfinite(d.mass) || d.mass <= 0)) {
    return "mass must be > 0 kg, got " + show(d.mass);
  }
  if (!std::isfinite(d.gravity_scale))
    return "gravity_scale must be finite, got " + show(d.gravity_scale);
  return validate_material(d.material);
}

}  // namespace

std::string WorldDef::validate() const {
  const auto range = [](const char* name, auto value, auto lo, auto hi) -> std::string {
    if (!(value >= lo && value <= hi)) {
      return std::string(name) + " must be " + show(lo) + ".." + show(hi) + ", got " + show(value);
    }
    return {};
  };
  if (!is_finite(gravity)) return "gravity must be finite, got " + show(gravity);
  for (const std::string& e : {
           range("iterations", iterations, 1, 1000),
           range("relax_iterations", relax_iterations, 0, 1000),
           range("substeps", substeps, 1, 64),
           range("baumgarte", baumgarte, Real(0), Real(1)),
           range("linear_slop", linear_slop, Real(0), Real(1)),
           range("max_correction_speed", max_correction_speed, Real(0), Real(1e6)),
           range("contact_hertz", contact_hertz, Real(0), Real(1e6)),
           range("contact_damping_ratio", contact_damping_ratio, Real(0), Real(1e6)),
           range("restitution_threshold", restitution_threshold, Real(0), Real(1e6)),
           range("max_speculative_distance", max_speculative_distance, Real(0), Real(1e3)),
           range("shock_mass_ratio", shock_mass_ratio, Real(1), Real(1e9)),
           range("max_linear_speed", max_linear_speed, Real(1e-3), Real(1e8)),
           range("max_angular_speed", max_angular_speed, Real(1e-3), Real(1e8)),
           range("sleep_linear_speed", sleep_linear_speed, Real(0), Real(1e6)),
           range("sleep_angular_speed", sleep_angular_speed, Real(0), Real(1e6)),
           range("time_to_sleep", time_to_sleep, Real(0), Real(1e6)),
           range("max_bodies", max_bodies, 1u, kMaxBodySlots),
           range("max_shapes", max_shapes, 1u, kMaxShapeSlots),
           range("max_projectiles", max_projectiles, 1u, kMaxProjectileSlots),
       }) {
    if (!e.empty()) return e;
  }
  return {};
}

// --- lifetime ---

Result<World> World::create(const WorldDef& def) {
  const std::string problem = def.validate();
  if (!problem.empty()) return invalid("WorldDef: " + problem);
  return World(std::make_unique<WorldImpl>(def));
}

World::World(std::unique_ptr<WorldImpl> impl) : impl_(std::move(impl)) {}
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

Result<BodyId> World::create_body(const BodyDef& def) {
  const std::string problem = validate_body(def);
  if (!problem.empty()) return invalid("BodyDef: " + problem);
  BodyStore& b = impl_->state.bodies;
  if (b.slots.full(impl_->def.max_bodies)) {
    return Error{ErrorCode::CapacityExceeded,
                 "create_body: world holds max_bodies = " + show(impl_->def.max_bodies) +
                     "; raise WorldDef::max_bodies"};
  }
  const std::uint32_t slot = b.create(def);
  impl_->mark_velocity_as_given(slot);
  impl_->configuration_changed();
  impl_->mark_for_move_event(slot, WorldImpl::kMoveMarkCreated);
  return b.id_of(slot);
}

Status World::destroy_body(BodyId id) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("destroy_body");
  impl_->remove_contacts_of(id.index);
  impl_->state.forces.remove_springs_of(id.index);
  impl_->state.bodies.destroy(id.index);
  impl_->configuration_changed();
  impl_->query_grid.mark_stale();
  return {};
}

void WorldImpl::remove_contacts_of(std::uint32_t slot) {
  const BodyId id = state.bodies.id_of(slot);
  const auto report_and_drop = [&](std::vector<Contact>& list, bool pair) {
    std::erase_if(list, [&](const Contact& c) {
      if (c.a != slot && !(pair && c.b == slot)) return false;
      if (c.touching && def.contact_events) {
        ContactTarget other = pair ? body_target(c.a == slot ? c.b : c.a) : shape_target(c.b);
        events.pending_end_events.push_back({id, other, state.bodies.user_data[slot]});
      }
      return true;
    });
  };
  report_and_drop(state.pair_contacts, true);
  report_and_drop(state.static_contacts, false);
  std::erase_if(state.sensor_overlaps, [&](std::uint64_t key) {
    return static_cast<std::uint32_t>(key >> 32) == slot || static_cast<std::uint32_t>(key) == slot;
  });
  std::erase_if(state.sensor_overlaps, [&](std::uint64_t key) {
    return static_cast<std::uint32_t>(key >> 32) == slot || static_cast<std::uint32_t>(key) == slot;
  });
}

bool World::is_valid(BodyId id) const {
  return impl_->state.bodies.valid(id);
}
std::uint32_t World::body_count() const {
  return impl_->state.bodies.slots.alive_count;
}

Result<BodyState> World::body_state(BodyId id) const {
  if (!impl_->state.bodies.valid(id)) return bad_handle("body_state");
  return impl_->state.bodies.state(id.index);
}

Status World::set_transform(BodyId id, const Vec3& position, const Quat& orientation) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("set_transform");
  if (!is_finite(position))
    return invalid("set_transform: position must be finite, got " + show(position));
  if (!is_finite(orientation) || orientation.squaredNorm() < Real(1e-12)) {
    return invalid("set_transform: orientation must be a finite, non-zero quaternion");
  }
  impl_->state.bodies.position[id.index] = position;
  impl_->state.bodies.orientation[id.index] = orientation.normalized();
  impl_->wake_body(id.index);
  impl_->mark_for_move_event(id.index, WorldImpl::kMoveMarkMoved);
  return {};
}

Status World::set_linear_velocity(BodyId id, const Vec3& velocity) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("set_linear_velocity");
  if (!is_finite(velocity))
    return invalid("set_linear_velocity: velocity must be finite, got " + show(velocity));
  if (impl_->state.bodies.has(id.index, kFlagFrozen)) return {};
  impl_->state.bodies.motion[id.index].linear_velocity = velocity;
  impl_->mark_velocity_as_given(id.index);
  impl_->wake_body(id.index);
  return {};
}

Status World::set_angular_velocity(BodyId id, const Vec3& velocity) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("set_angular_velocity");
  if (!is_finite(velocity))
    return invalid("set_angular_velocity: velocity must be finite, got " + show(velocity));
  BodyStore& b = impl_->state.bodies;
  if (b.has(id.index, kFlagLockRotation) || b.has(id.index, kFlagFrozen)) return {};
  b.motion[id.index].angular_velocity = velocity;
  impl_->wake_body(id.index);
  return {};
}

Status World::apply_force(BodyId id, const Vec3& force) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("apply_force");
  const Vec3 total = impl_->state.bodies.force[id.index] + force;
  if (!is_finite(force) || !is_finite(total))
    return invalid("apply_force: force must be finite, got " + show(force));
  impl_->state.bodies.force[id.index] = total;
  impl_->wake_body(id.index);
  return {};
}

Status World::apply_torque(BodyId id, const Vec3& torque) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("apply_torque");
  const Vec3 total = impl_->state.bodies.torque[id.index] + torque;
  if (!is_finite(torque) || !is_finite(total))
    return invalid("apply_torque: torque must be finite, got " + show(torque));
  impl_->state.bodies.torque[id.index] = total;
  impl_->wake_body(id.index);
  return {};
}

Status World::apply_impulse(BodyId id, const Vec3& impulse, const Vec3& point) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("apply_impulse");
  if (!is_finite(impulse) || !is_finite(point)) {
    return invalid("apply_impulse: impulse and point must be finite, got " + show(impulse) +
                   " at " + show(point));
  }
  BodyStore& b = impl_->state.bodies;
  if (b.has(id.index, kFlagFrozen)) return {};
  Motion& m = b.motion[id.index];
  const Vec3 v = m.linear_velocity + m.inverse_mass * impulse;
  const Vec3 w =
      m.angular_velocity + m.inverse_inertia * (point - b.position[id.index]).cross(impulse);
  if (!is_finite(v) || !is_finite(w))
    return invalid("apply_impulse: resulting velocity is not finite");
  m.linear_velocity = v;
  m.angular_velocity = w;
  impl_->wake_body(id.index);
  return {};
}

Status World::wake(BodyId id) {
  if (!impl_->state.bodies.valid(id)) return bad_handle("wake");
  impl_->wake_body(id.index);
  return {};
}

// --- static geometry ---

namespace {

Status check_shape_capacity(const StaticGeometry& statics, const WorldDef& def) {
  if (statics.slots().full(def.max_shapes)) {
    return Error{ErrorCode::CapacityExceeded, "world holds max_shapes = " + show(def.max_shapes) +
                                                  "; raise WorldDef::max_shapes"};
  }
  return {};
}

}  // namespace

Result<ShapeId> World::add_plane(const PlaneDef& def) {
  if (!is_finite(def.normal) || def.normal.norm() < Real(1e-6)) {
    return invalid("PlaneDef: normal must be finite and non-zero, got " + show(def.normal));
  }
  if (!std::isfinite(def.offset)) return invalid("PlaneDef: offset must be finite");
  if (const std::string e = validate_material(def.material); !e.empty())
    return invalid("PlaneDef: " + e);
  if (Status s = check_shape_capacity(impl_->state.statics, impl_->def); !s) return s.error();
  StaticShape shape;
  shape.type = ShapeType::Plane;
  shape.plane_normal = def.normal.normalized();
  shape.plane_offset = def.offset;
  shape.material = def.material;
  shape.filter = def.filter;
  return impl_->add_shape(std::move(shape));
}

Result<ShapeId> World::add_box(const BoxDef& def) {
  if (!is_finite(def.center))
    return invalid("BoxDef: center must be finite, got " + show(def.center));
  if (!is_finite(def.orientation) || def.orientation.squaredNorm() < Real(1e-12)) {
    return invalid("BoxDef: orientation must be a finite, non-zero quaternion");
  }
  if (!is_finite(def.half_extents) || def.half_extents.minCoeff() <= 0) {
    return invalid("BoxDef: half_extents must be finite and > 0 m, got " + show(def.half_extents));
  }
  if (const std::string e = validate_material(def.material); !e.empty())
    return invalid("BoxDef: " + e);
  if (Status s = check_shape_capacity(impl_->state.statics, impl_->def); !s) return s.error();
  StaticShape shape;
  shape.type = ShapeType::Box;
  shape.box_center = def.center;
  shape.box_orientation = def.orientation.normalized();
  shape.box_half_extents = def.half_extents;
  shape.material = def.material;
  shape.filter = def.filter;
  return impl_->add_shape(std::move(shape));
}

Result<ShapeId> World::add_mesh(const MeshDef& def) {
  if (def.indices.empty() || def.indices.size() % 3 != 0) {
    return invalid("MeshDef: indices must be a non-empty multiple of 3, got " +
                   show(def.indices.size()));
  }
  if (def.indices.size() / 3 > kMaxMeshTriangles) {
    return invalid("MeshDef: at most " + show(kMaxMeshTriangles) + " triangles per mesh, got " +
                   show(def.indices.size() / 3) + "; split the mesh");
  }
  for (std::size_t i = 0; i < def.vertices.size(); ++i) {
    if (!is_finite(def.vertices[i]))
      return invalid("MeshDef: vertex " + show(i) + " is not finite");
  }
  for (std::size_t i = 0; i < def.indices.size(); ++i) {
    if (def.indices[i] >= def.vertices.size()) {
      return invalid("MeshDef: index " + show(i) + " is " + show(def.indices[i]) +
                     ", but there are only " + show(def.vertices.size()) + " vertices");
    }
  }
  if (const std::string e = validate_material(def.material); !e.empty())
    return invalid("MeshDef: " + e);
  if (Status s = check_shape_capacity(impl_->state.statics, impl_->def); !s) return s.error();
  StaticShape shape;
  shape.type = ShapeType::Mesh;
  shape.vertices = def.vertices;
  shape.indices = def.indices;
  shape.material = def.material;
  shape.filter = def.filter;
  return impl_->add_shape(std::move(shape));
}

ShapeId WorldImpl::add_shape(StaticShape shape) {
  configuration_changed();
  return state.statics.id_of(state.statics.add(std::move(shape)));
}

Status World::remove_shape(ShapeId id) {
  if (!impl_->state.statics.valid(id))
    return Error{ErrorCode::InvalidHandle, "remove_shape: null, stale or unknown ShapeId"};
  WorldImpl& w = *impl_;
  std::erase_if(w.state.static_contacts, [&](const Contact& c) {
    if (c.b != id.index) return false;
    if (c.touching && w.def.contact_events) {
      w.events.pending_end_events.push_back(
          {w.state.bodies.id_of(c.a), w.shape_target(id.index), w.state.bodies.user_data[c.a]});
    }
    return true;
  });
  w.wake_all();  // whatever rested on it must fall
  w.state.statics.remove(id.index);
  w.configuration_changed();
  return {};
}

std::uint32_t World::shape_count() const {
  return impl_->state.statics.count();
}

// --- force fields ---

namespace {

Status check_force_capacity(const ForceFields& forces) {
  if (forces.slots().full(ForceFields::kMaxFields)) {
    return Error{ErrorCode::CapacityExceeded,
                 "world holds " + show(ForceFields::kMaxFields) + " force fields at most"};
  }
  return {};
}

}  // namespace

Result<ForceId> World::add_spring(const SpringDef& def) {
  WorldImpl& w = *impl_;
  if (!w.state.bodies.valid(def.body)) return bad_handle("add_spring");
  if (w.state.bodies.has(def.body.index, kFlagKinematic))
    return invalid("SpringDef: body must be dynamic (kinematic state.bodies ignore state.forces)");
  if (!is_finite(def.anchor))
    return invalid("SpringDef: anchor must be finite, got " + show(def.anchor));
  if (!std::isfinite(def.stiffness) || def.stiffness <= 0)
    return invalid("SpringDef: stiffness must be > 0 N/m, got " + show(def.stiffness));
  if (!std::isfinite(def.rest_length) || def.rest_length < 0)
    return invalid("SpringDef: rest_length must be >= 0 m, got " + show(def.rest_length));
  if (!std::isfinite(def.damping) || def.damping < 0)
    return invalid("SpringDef: damping must be >= 0 N·s/m, got " + show(def.damping));
  if (Status s = check_force_capacity(w.state.forces); !s) return s.error();
  ForceField field;
  field.kind = ForceKind::Spring;
  field.body = def.body.index;
  field.point = def.anchor;
  field.stiffness = def.stiffness;
  field.rest_length = def.rest_length;
  field.damping = def.damping;
  w.wake_body(def.body.index);
  w.configuration_changed();
  return w.state.forces.id_of(w.state.forces.add(field));
}

Result<ForceId> World::add_attractor(const AttractorDef& def) {
  WorldImpl& w = *impl_;
  if (!is_finite(def.center))
    return invalid("AttractorDef: center must be finite, got " + show(def.center));
  if (!std::isfinite(def.strength) || def.strength <= 0)
    return invalid("AttractorDef: strength must be > 0 m³/s², got " + show(def.strength));
  if (!std::isfinite(def.min_distance) || def.min_distance <= 0)
    return invalid("AttractorDef: min_distance must be > 0 m, got " + show(def.min_distance));
  if (Status s = check_force_capacity(w.state.forces); !s) return s.error();
  ForceField field;
  field.kind = ForceKind::Attractor;
  field.point = def.center;
  field.stiffness = def.strength;
  field.min_distance = def.min_distance;
  field.mask = def.mask;
  w.wake_all();
  w.configuration_changed();
  return w.state.forces.id_of(w.state.forces.add(field));
}

Status World::remove_force(ForceId id) {
  WorldImpl& w = *impl_;
  if (!w.state.forces.valid(id))
    return Error{ErrorCode::InvalidHandle, "remove_force: null, stale or unknown ForceId"};
  const ForceField& field = w.state.forces.fields()[id.index];
  if (field.kind == ForceKind::Spring) {
    w.wake_body(field.body);
  } else {
    w.wake_all();
  }
  w.state.forces.remove(id.index);
  w.configuration_changed();
  return {};
}

std::uint32_t World::force_count() const {
  return impl_->state.forces.count();
}

// --- simulation ---

Status World::step(Real dt_s) {
  if (!std::isfinite(dt_s) || dt_s <= 0 || dt_s > 1) {
    return invalid("step: dt_s must be finite and in (0, 1] s, got " + show(dt_s));
  }
  return impl_->step(dt_s);
}

Status WorldImpl::step(Real step_dt) {
  profile = StepProfile{};
  ProfileTimer timer;
  begin_step(step_dt);
  find_pairs();
  wake_touching_islands();
  gather_awake_bodies();
  timer.lap(profile.broad_phase_ms);
  update_contacts();
  timer.lap(profile.narrow_phase_ms);
  solve(step_dt, timer);  // laps into solve_ms and integrate_ms
  solve_continuous();
  freeze_nonfinite();
  timer.lap(profile.continuous_ms);
  step_projectiles();
  timer.lap(profile.projectiles_ms);
  update_sleep(step_dt);
  timer.lap(profile.sleep_ms);
  report_events();
  report_body_moves();
  timer.lap(profile.events_ms);
  end_step();
  query_grid.mark_stale();

  profile.total_ms = timer.total_ms();
  profile.bodies_awake = static_cast<int>(scratch.awake_list.size());
  return {};
}

void WorldImpl::begin_step(Real step_dt) {
  scratch.dt = step_dt;
  events.clear_step();
  const std::uint32_t slots = state.bodies.slot_count();
  scratch.speculative_margin.resize(slots);
  // A contact is created while the gap is below the margin: enough for this step's motion (so
  // nothing sinks in before it is stopped), capped so fast bodies do not inflate the grid.
  // A fast body moving more than its radius per step is swept instead (solve_continuous), and
  // keeps only the base margin: a wide speculative contact would stop it against anything it
  // merely passes within the margin of (a ghost hit).
  const Real base = 4 * def.linear_slop;
  for (std::uint32_t s = 0; s < slots; ++s) {
    const Real move = state.bodies.motion[s].linear_velocity.norm() * step_dt;
    const bool swept =
        def.enable_continuous && state.bodies.has(s, kFlagFast) && move > state.bodies.radius[s];
    scratch.speculative_margin[s] =
        swept ? base : base + std::min(move, def.max_speculative_distance);
  }
}

void WorldImpl::gather_awake_bodies() {
  const std::uint32_t slots = state.bodies.slot_count();
  scratch.awake_list.clear();
  for (std::uint32_t s = 0; s < slots; ++s) {
    if (state.bodies.alive(s) && (state.bodies.flags[s] & (kFlagSleeping | kFlagFrozen)) == 0)
      scratch.awake_list.push_back(s);
  }
  scratch.start_position = state.bodies.position;
  scratch.start_orientation = state.bodies.orientation;
  scratch.contact_count.assign(slots, 0);
}

void WorldImpl::wake_all() {
  for (std::uint32_t s = 0; s < state.bodies.slot_count(); ++s) {
    if (state.bodies.alive(s)) wake_body(s);
  }
}

void WorldImpl::freeze_body(std::uint32_t slot) {
  if (state.bodies.has(slot, kFlagFrozen)) return;
  state.bodies.flags[slot] |= kFlagFrozen;
  state.bodies.motion[slot] =
      Motion{};  // zero velocity, zero inverse mass: an obstacle, not a carrier
  scratch.nonfinite_slots.push_back(slot);
}

void WorldImpl::freeze_nonfinite() {
  for (const std::uint32_t s : scratch.awake_list) {
    const Motion& m = state.bodies.motion[s];
    if (!is_finite(state.bodies.position[s]) || !is_finite(state.bodies.orientation[s]) ||
        !is_finite(m.linear_velocity) || !is_finite(m.angular_velocity)) {
      freeze_body(s);
    }
  }
  for (const std::uint32_t s : scratch.nonfinite_slots) {
    state.bodies.position[s] = scratch.start_position[s];
    state.bodies.orientation[s] = scratch.start_orientation[s];
    events.nonfinite_events.push_back({state.bodies.id_of(s)});
  }
  scratch.nonfinite_slots.clear();
}

void WorldImpl::end_step() {
  for (const std::uint32_t s : scratch.awake_list) {
    state.bodies.force[s].setZero();
    state.bodies.torque[s].setZero();
  }
  ++state.steps;
}

const StepProfile& World::profile() const {
  return impl_->profile;
}
const WorldDef& World::definition() const {
  return impl_->def;
}
Status World::set_gravity(const Vec3& gravity) {
  if (!is_finite(gravity))
    return invalid("set_gravity: gravity must be finite, got " + show(gravity));
  impl_->state.gravity = gravity;
  impl_->def.gravity = gravity;
  impl_->wake_all();
  return {};
}
std::uint64_t World::step_count() const {
  return impl_->state.steps;
}

std::span<const ContactBeginEvent> World::contact_begin_events() const {
  return impl_->events.begin_events;
}
std::span<const ContactEndEvent> World::contact_end_events() const {
  return impl_->events.end_events;
}
std::span<const ContactImpulseEvent> World::contact_impulse_events() const {
  return impl_->events.impulse_events;
}
std::span<const NonFiniteEvent> World::nonfinite_events() const {
  return impl_->events.nonfinite_events;
}

}  // namespace ricochet::physics
