/// State hash, save and restore. The save image is little-endian field by field (no struct
/// memcpy), versioned, and fully validated on restore: a truncated or forged image is rejected
/// with CorruptState and the world is left unchanged.
///
/// Layout: "RCPW" | version u32 | sizeof(Real) u8 | steps u64 | gravity | bodies | free slots |
///         static shapes | static free slots | pair contacts | static contacts | sensor keys |
///         force fields | force free slots | projectiles | projectile free slots

#include <algorithm>
#include <cstring>

#include "math_util.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

constexpr std::uint32_t kMagic = 0x57504352;  // "RCPW"
constexpr std::uint32_t kVersion = 3;         // 2: force fields, 3: projectiles

class Writer {
 public:
  template <class T>
  void pod(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void vec(const Vec3& v) { pod(v.x()), pod(v.y()), pod(v.z()); }
  void quat(const Quat& q) { pod(q.w()), pod(q.x()), pod(q.y()), pod(q.z()); }
  std::vector<std::uint8_t> bytes;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  template <class T>
  bool pod(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (bytes_.size() - offset_ < sizeof(T)) return fail("truncated");
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return true;
  }
  bool real(Real& value) { return pod(value) && (is_finite(value) || fail("non-finite number")); }
  bool vec(Vec3& v) { return real(v.x()) && real(v.y()) && real(v.z()); }
  bool quat(Quat& q) { return real(q.w()) && real(q.x()) && real(q.y()) && real(q.z()); }
  /// A count that must be at most `limit` and fit in the remaining bytes at `min_size` each.
  bool count(std::uint32_t& n, std::uint32_t limit, std::size_t min_size) {
    if (!pod(n)) return false;
    if (n > limit) return fail("count above limit");
    if (static_cast<std::size_t>(n) * min_size > bytes_.size() - offset_)
      return fail("count exceeds data");
    return true;
  }
  bool fail(const char* why) {
    if (error.empty()) error = std::string(why) + " at byte " + std::to_string(offset_);
    return false;
  }
  bool at_end() const { return offset_ == bytes_.size(); }
  std::string error;

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t offset_ = 0;
};

void write_contact(Writer& w, const Contact& c) {
  w.pod(c.key), w.pod(c.a), w.pod(c.b);
  w.vec(c.normal), w.pod(c.separation), w.pod(c.ra), w.pod(c.rb);
  w.pod(c.friction), w.pod(c.restitution), w.pod(c.rolling);
  w.pod(c.normal_impulse), w.vec(c.friction_impulse), w.vec(c.rolling_impulse);
  w.pod(c.total_normal_impulse), w.pod(c.max_normal_impulse), w.pod(c.relative_velocity);
  w.vec(c.point), w.pod(static_cast<std::uint8_t>(c.touching));
}

bool read_contact(Reader& r, Contact& c) {
  std::uint8_t touching = 0;
  const bool ok = r.pod(c.key) && r.pod(c.a) && r.pod(c.b) && r.vec(c.normal) &&
                  r.real(c.separation) && r.real(c.ra) && r.real(c.rb) && r.real(c.friction) &&
                  r.real(c.restitution) && r.real(c.rolling) && r.real(c.normal_impulse) &&
                  r.vec(c.friction_impulse) && r.vec(c.rolling_impulse) &&
                  r.real(c.total_normal_impulse) && r.real(c.max_normal_impulse) &&
                  r.real(c.relative_velocity) && r.vec(c.point) && r.pod(touching);
  c.touching = touching != 0;
  return ok;
}

constexpr std::size_t kMinContactBytes = 8 + 4 + 4;
constexpr std::size_t kMinForceBytes = 1 + 4 + 1;

void write_force(Writer& w, const ForceField& f) {
  w.pod(static_cast<std::uint8_t>(f.kind)), w.pod(f.generation);
  w.pod(static_cast<std::uint8_t>(f.alive));
  if (!f.alive) return;
  w.pod(f.body), w.vec(f.point), w.pod(f.stiffness), w.pod(f.rest_length), w.pod(f.damping);
  w.pod(f.min_distance), w.pod(f.mask);
}

/// Reads one field and checks it as add_spring/add_attractor would; empty when valid.
std::string read_force(Reader& r, const BodyStore& bodies, ForceField& f) {
  std::uint8_t kind = 0, alive = 0;
  if (!r.pod(kind) || !r.pod(f.generation) || !r.pod(alive)) return r.error;
  if (kind > static_cast<std::uint8_t>(ForceKind::Attractor)) return "unknown force field kind";
  f.kind = static_cast<ForceKind>(kind);
  f.alive = alive != 0;
  if (!f.alive) return {};
  if (!r.pod(f.body) || !r.vec(f.point) || !r.real(f.stiffness) || !r.real(f.rest_length) ||
      !r.real(f.damping) || !r.real(f.min_distance) || !r.pod(f.mask)) {
    return r.error;
  }
  if (f.generation == 0) return "live force field with null generation";
  if (f.stiffness <= 0 || f.rest_length < 0 || f.damping < 0 || f.min_distance < 0)
    return "force field with out-of-range parameters";
  if (f.kind == ForceKind::Spring && (f.body >= bodies.slot_count() || !bodies.alive(f.body) ||
                                      bodies.has(f.body, kFlagKinematic))) {
    return "spring names a missing or kinematic body";
  }
  if (f.kind == ForceKind::Attractor && f.min_distance <= 0)
    return "attractor with min_distance <= 0";
  return {};
}

/// Reads the projectile slots and free list, checking each as create_projectile would; empty
/// when valid.
std::string read_projectiles(Reader& in, const WorldDef& def, ProjectileStore& p) {
  std::uint32_t slots = 0;
  if (!in.count(slots, def.max_projectiles, 5)) return in.error;
  p = ProjectileStore{};
  p.resize(slots);
  for (std::uint32_t s = 0; s < slots; ++s) {
    if (!in.pod(p.generation[s]) || !in.pod(p.alive[s])) return in.error;
    if (p.alive[s] > 1) return "projectile alive flag not 0 or 1";
    if (!p.alive[s]) continue;
    ++p.alive_count;
    if (!in.vec(p.position[s]) || !in.vec(p.velocity[s]) || !in.real(p.radius[s]) ||
        !in.real(p.gravity_scale[s]) || !in.pod(p.filter[s].layer) || !in.pod(p.filter[s].mask) ||
        !in.pod(p.ignore[s].index) || !in.pod(p.ignore[s].generation) || !in.pod(p.user_data[s])) {
      return in.error;
    }
    if (p.generation[s] == 0) return "live projectile with null generation";
    if (p.radius[s] < 0 || p.velocity[s].norm() > def.max_linear_speed)
      return "projectile with negative radius or speed above max_linear_speed";
  }
  std::uint32_t free_count = 0;
  if (!in.count(free_count, slots, 4)) return in.error;
  p.free_slots.resize(free_count);
  for (std::uint32_t& s : p.free_slots) {
    if (!in.pod(s)) return in.error;
    if (s >= slots || p.alive[s]) return "projectile free list names a live or missing slot";
  }
  return {};
}

}  // namespace

std::uint64_t World::state_hash() const {
  const WorldImpl& w = *impl_;
  Fnv1a h;
  h.add_value(w.state.steps);
  const BodyStore& b = w.state.bodies;
  for (std::uint32_t s = 0; s < b.slot_count(); ++s) {
    if (!b.alive(s)) continue;
    h.add_value(s);
    h.add_value(b.generation[s]);
    h.add_value(b.flags[s]);
    h.add(b.position[s].data(), sizeof(Real) * 3);
    h.add(b.orientation[s].coeffs().data(), sizeof(Real) * 4);
    h.add(b.motion[s].linear_velocity.data(), sizeof(Real) * 3);
    h.add(b.motion[s].angular_velocity.data(), sizeof(Real) * 3);
    h.add_value(b.sleep_time[s]);
  }
  for (const auto* list : {&w.state.pair_contacts, &w.state.static_contacts}) {
    for (const Contact& c : *list) {
      h.add_value(c.key);
      h.add_value(c.normal_impulse);
      h.add(c.friction_impulse.data(), sizeof(Real) * 3);
      h.add(c.rolling_impulse.data(), sizeof(Real) * 3);
    }
  }
  const std::vector<ForceField>& fields = w.state.forces.fields();
  for (std::uint32_t s = 0; s < fields.size(); ++s) {
    const ForceField& f = fields[s];
    if (!f.alive) continue;
    h.add_value(s);
    h.add_value(static_cast<std::uint8_t>(f.kind));
    h.add_value(f.body);
    h.add(f.point.data(), sizeof(Real) * 3);
    h.add_value(f.stiffness);
    h.add_value(f.rest_length);
    h.add_value(f.damping);
    h.add_value(f.min_distance);
    h.add_value(f.mask);
  }
  const ProjectileStore& p = w.state.projectiles;
  for (std::uint32_t s = 0; s < p.slot_count(); ++s) {
    if (!p.alive[s]) continue;
    h.add_value(s);
    h.add_value(p.generation[s]);
    h.add(p.position[s].data(), sizeof(Real) * 3);
    h.add(p.velocity[s].data(), sizeof(Real) * 3);
  }
  return h.value();
}

std::vector<std::uint8_t> World::save_state() const {
  const WorldImpl& w = *impl_;
  Writer out;
  out.pod(kMagic), out.pod(kVersion), out.pod(static_cast<std::uint8_t>(sizeof(Real)));
  out.pod(w.state.steps);
  out.vec(w.state.gravity);
  const BodyStore& b = w.state.bodies;
  out.pod(b.slot_count());
  for (std::uint32_t s = 0; s < b.slot_count(); ++s) {
    out.pod(b.generation[s]), out.pod(b.flags[s]);
    if (!b.alive(s)) continue;
    out.vec(b.position[s]), out.quat(b.orientation[s]);
    const Motion& m = b.motion[s];
    out.vec(m.linear_velocity), out.pod(m.inverse_mass), out.vec(m.angular_velocity),
        out.pod(m.inverse_inertia);
    out.vec(b.force[s]), out.vec(b.torque[s]);
    out.pod(b.radius[s]), out.pod(b.mass_inverse_original[s]),
        out.pod(b.inertia_inverse_original[s]);
    out.pod(b.gravity_scale[s]);
    const Material& mat = b.material[s];
    out.pod(mat.restitution), out.pod(mat.friction), out.pod(mat.rolling_resistance);
    out.pod(b.filter[s].layer), out.pod(b.filter[s].mask);
    out.pod(b.sleep_time[s]), out.pod(b.user_data[s]);
  }
  out.pod(static_cast<std::uint32_t>(b.free_slots.size()));
  for (const std::uint32_t s : b.free_slots) out.pod(s);

  const auto& shapes = w.state.statics.shapes();
  out.pod(static_cast<std::uint32_t>(shapes.size()));
  for (const StaticShape& shape : shapes) {
    out.pod(static_cast<std::uint8_t>(shape.type)), out.pod(shape.generation);
    out.pod(static_cast<std::uint8_t>(shape.alive));
    if (!shape.alive) continue;
    out.pod(shape.material.restitution), out.pod(shape.material.friction);
    out.pod(shape.material.rolling_resistance);
    out.pod(shape.filter.layer), out.pod(shape.filter.mask);
    out.vec(shape.plane_normal), out.pod(shape.plane_offset);
    out.vec(shape.box_center), out.quat(shape.box_orientation), out.vec(shape.box_half_extents);
    out.pod(static_cast<std::uint32_t>(shape.vertices.size()));
    for (const Vec3& v : shape.vertices) out.vec(v);
    out.pod(static_cast<std::uint32_t>(shape.indices.size()));
    for (const std::uint32_t i : shape.indices) out.pod(i);
  }
  out.pod(static_cast<std::uint32_t>(w.state.statics.free_slots().size()));
  for (const std::uint32_t s : w.state.statics.free_slots()) out.pod(s);

  for (const auto* list : {&w.state.pair_contacts, &w.state.static_contacts}) {
    out.pod(static_cast<std::uint32_t>(list->size()));
    for (const Contact& c : *list) write_contact(out, c);
  }
  out.pod(static_cast<std::uint32_t>(w.state.sensor_overlaps.size()));
  for (const std::uint64_t key : w.state.sensor_overlaps) out.pod(key);
  out.pod(static_cast<std::uint32_t>(w.state.forces.fields().size()));
  for (const ForceField& f : w.state.forces.fields()) write_force(out, f);
  out.pod(static_cast<std::uint32_t>(w.state.forces.free_slots().size()));
  for (const std::uint32_t s : w.state.forces.free_slots()) out.pod(s);
  const ProjectileStore& p = w.state.projectiles;
  out.pod(p.slot_count());
  for (std::uint32_t s = 0; s < p.slot_count(); ++s) {
    out.pod(p.generation[s]), out.pod(p.alive[s]);
    if (!p.alive[s]) continue;
    out.vec(p.position[s]), out.vec(p.velocity[s]), out.pod(p.radius[s]),
        out.pod(p.gravity_scale[s]);
    out.pod(p.filter[s].layer), out.pod(p.filter[s].mask);
    out.pod(p.ignore[s].index), out.pod(p.ignore[s].generation), out.pod(p.user_data[s]);
  }
  out.pod(static_cast<std::uint32_t>(p.free_slots.size()));
  for (const std::uint32_t s : p.free_slots) out.pod(s);
  return std::move(out.bytes);
}

Status World::restore_state(std::span<const std::uint8_t> bytes) {
  const WorldImpl& current = *impl_;
  Reader in(bytes);
  const auto corrupt = [&](const std::string& why) {
    return Status(Error{ErrorCode::CorruptState, "restore_state: " + why});
  };
  std::uint32_t magic = 0, version = 0;
  std::uint8_t real_size = 0;
  if (!in.pod(magic) || magic != kMagic) return corrupt("not a Ricochet physics state (bad magic)");
  if (!in.pod(version) || version != kVersion) {
    return corrupt("state version " + std::to_string(version) + ", this build reads " +
                   std::to_string(kVersion));
  }
  if (!in.pod(real_size) || real_size != sizeof(Real)) {
    return corrupt("state saved with " + std::to_string(real_size * 8) +
                   "-bit reals, this build uses " + std::to_string(sizeof(Real) * 8));
  }
  WorldImpl next(current.def);
  if (!in.pod(next.state.steps) || !in.vec(next.state.gravity)) return corrupt(in.error);

  BodyStore& b = next.state.bodies;
  std::uint32_t slots = 0;
  if (!in.count(slots, std::min(current.def.max_bodies, kMaxBodySlots), 6))
    return corrupt(in.error);
  BodyDef placeholder;
  for (std::uint32_t s = 0; s < slots; ++s) {
    const std::uint32_t slot = b.create(placeholder);
    std::uint32_t generation = 0;
    std::uint16_t flags = 0;
    if (!in.pod(generation) || !in.pod(flags)) return corrupt(in.error);
    b.generation[slot] = generation;
    b.flags[slot] = flags;
    if ((flags & kFlagAlive) == 0) {
      if (flags != 0) return corrupt("dead body slot with flags set");
      continue;
    }
    if (generation == 0) return corrupt("live body with null generation");
    Motion& m = b.motion[slot];
    Material& mat = b.material[slot];
    if (!in.vec(b.position[slot]) || !in.quat(b.orientation[slot]) || !in.vec(m.linear_velocity) ||
        !in.real(m.inverse_mass) || !in.vec(m.angular_velocity) || !in.real(m.inverse_inertia) ||
        !in.vec(b.force[slot]) || !in.vec(b.torque[slot]) || !in.real(b.radius[slot]) ||
        !in.real(b.mass_inverse_original[slot]) || !in.real(b.inertia_inverse_original[slot]) ||
        !in.real(b.gravity_scale[slot]) || !in.real(mat.restitution) || !in.real(mat.friction) ||
        !in.real(mat.rolling_resistance) || !in.pod(b.filter[slot].layer) ||
        !in.pod(b.filter[slot].mask) || !in.real(b.sleep_time[slot]) ||
        !in.pod(b.user_data[slot])) {
      return corrupt(in.error);
    }
    if (b.radius[slot] <= 0 || m.inverse_mass < 0 || m.inverse_inertia < 0)
      return corrupt("body with invalid mass or radius");
  }
  // Recount: create() counted every slot as alive.
  b.alive_count = 0;
  for (std::uint32_t s = 0; s < slots; ++s) b.alive_count += b.alive(s) ? 1 : 0;
  b.free_slots.clear();
  std::uint32_t free_count = 0;
  if (!in.count(free_count, slots, 4)) return corrupt(in.error);
  for (std::uint32_t k = 0; k < free_count; ++k) {
    std::uint32_t s = 0;
    if (!in.pod(s)) return corrupt(in.error);
    if (s >= slots || b.alive(s)) return corrupt("free list names a live or missing body slot");
    b.free_slots.push_back(s);
  }

  std::uint32_t shape_count = 0;
  if (!in.count(shape_count, std::min(current.def.max_shapes, kMaxShapeSlots), 6))
    return corrupt(in.error);
  std::vector<StaticShape> shapes(shape_count);
  for (StaticShape& shape : shapes) {
    std::uint8_t type = 0, alive = 0;
    if (!in.pod(type) || !in.pod(shape.generation) || !in.pod(alive)) return corrupt(in.error);
    if (type > static_cast<std::uint8_t>(ShapeType::Mesh)) return corrupt("unknown shape type");
    shape.type = static_cast<ShapeType>(type);
    shape.alive = alive != 0;
    if (!shape.alive) continue;
    std::uint32_t vertex_count = 0, index_count = 0;
    if (!in.real(shape.material.restitution) || !in.real(shape.material.friction) ||
        !in.real(shape.material.rolling_resistance) || !in.pod(shape.filter.layer) ||
        !in.pod(shape.filter.mask) || !in.vec(shape.plane_normal) || !in.real(shape.plane_offset) ||
        !in.vec(shape.box_center) || !in.quat(shape.box_orientation) ||
        !in.vec(shape.box_half_extents) ||
        !in.count(vertex_count, 3 * kMaxMeshTriangles, 3 * sizeof(Real))) {
      return corrupt(in.error);
    }
    shape.vertices.resize(vertex_count);
    for (Vec3& v : shape.vertices) {
      if (!in.vec(v)) return corrupt(in.error);
    }
    if (!in.count(index_count, 3 * kMaxMeshTriangles, 4)) return corrupt(in.error);
    shape.indices.resize(index_count);
    for (std::uint32_t& i : shape.indices) {
      if (!in.pod(i)) return corrupt(in.error);
      if (i >= vertex_count) return corrupt("mesh index out of range");
    }
    if (index_count % 3 != 0) return corrupt("mesh index count not a multiple of 3");
  }
  std::uint32_t shape_free_count = 0;
  if (!in.count(shape_free_count, shape_count, 4)) return corrupt(in.error);
  std::vector<std::uint32_t> shape_free(shape_free_count);
  for (std::uint32_t& s : shape_free) {
    if (!in.pod(s)) return corrupt(in.error);
    if (s >= shape_count || shapes[s].alive)
      return corrupt("shape free list names a live or missing slot");
  }
  next.state.statics.assign(std::move(shapes), std::move(shape_free));

  for (auto* list : {&next.state.pair_contacts, &next.state.static_contacts}) {
    std::uint32_t n = 0;
    if (!in.count(n, 1u << 28, kMinContactBytes)) return corrupt(in.error);
    list->resize(n);
    for (Contact& c : *list) {
      if (!read_contact(in, c)) return corrupt(in.error);
      if (c.a >= slots || !b.alive(c.a)) return corrupt("contact names a missing body");
      const bool pair = list == &next.state.pair_contacts;
      if (pair ? (c.b >= slots || !b.alive(c.b))
               : (c.b >= shape_count || !next.state.statics.shape(c.b).alive)) {
        return corrupt("contact names a missing body or shape");
      }
    }
  }
  std::uint32_t overlap_count = 0;
  if (!in.count(overlap_count, 1u << 28, 8)) return corrupt(in.error);
  next.state.sensor_overlaps.resize(overlap_count);
  for (std::uint64_t& key : next.state.sensor_overlaps) {
    if (!in.pod(key)) return corrupt(in.error);
  }
  std::uint32_t force_count = 0;
  if (!in.count(force_count, ForceFields::kMaxFields, kMinForceBytes)) return corrupt(in.error);
  std::vector<ForceField> fields(force_count);
  for (ForceField& f : fields) {
    if (const std::string why = read_force(in, b, f); !why.empty()) return corrupt(why);
  }
  std::uint32_t force_free_count = 0;
  if (!in.count(force_free_count, force_count, 4)) return corrupt(in.error);
  std::vector<std::uint32_t> force_free(force_free_count);
  for (std::uint32_t& s : force_free) {
    if (!in.pod(s)) return corrupt(in.error);
    if (s >= force_count || fields[s].alive)
      return corrupt("force free list names a live or missing slot");
  }
  next.state.forces.assign(std::move(fields), std::move(force_free));
  if (const std::string why = read_projectiles(in, current.def, next.state.projectiles);
      !why.empty())
    return corrupt(why);
  if (!in.at_end()) return corrupt("trailing bytes after the state");

  next.def.gravity = next.state.gravity;
  *impl_ = std::move(next);
  return {};
}

}  // namespace ricochet::physics
