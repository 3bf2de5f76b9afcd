/// State images: save, restore and hash. An image is little-endian, field by field (no struct
/// memcpy, so no padding bytes), versioned, and fully validated on restore: a truncated or forged
/// image is refused with CorruptState naming the field, and the world is left unchanged.
///
/// The image has two sections. The configuration is what only API calls change (body slots and
/// each body's definition, static shapes, force fields); the dynamic state is what a step changes.
/// A StateParts::Dynamic image carries only the dynamic state and the configuration's
/// fingerprint (FNV-1a of its section), so it is small and restores in place, without touching
/// the shapes' hierarchy or reallocating: a rewind per tick.
///
///   header   "RCPW" u32 | version u32 | sizeof(Real) u8 | has_config u8 | fingerprint u64 |
///            config bytes u32 (0 without config)
///   config   body pool | per live body: flags u16 (kConfigFlags), radius, inverse mass,
///              inverse inertia, gravity scale, material (3 reals), filter (2 u32), user data u64
///            shape pool | per live shape: type u8, material, filter, plane normal, plane offset,
///              box centre, box orientation, box half extents, vertex count u32, vertices,
///              index count u32, indices u32
///            force pool | per live field: kind u8, body u32, point, stiffness, rest length,
///              damping, min distance, mask u32
///   dynamic  steps u64 | gravity
///            per live body: flags u16 (kStateFlags), position, orientation (w x y z), linear
///              velocity, angular velocity, sleep time
///            loads: count u32 | per body with a force or torque: slot u32, force, torque
///            pair contacts, static contacts: count u32 | key u64, contact bits u8 (touching,
///              has friction impulse, has rolling impulse), normal impulse, [friction impulse],
///              [rolling impulse]; only contacts that touch or carry an impulse (the others
///              change nothing in the next step)
///            sensor overlaps: count u32 | keys u64, ascending
///            projectile pool | per live projectile: position, velocity, shape bit u8 (1: the
///              radius, gravity scale and filter of the previous live projectile), [radius,
///              gravity scale, filter], ignore (index u32, generation u32), user data u64
///   pool     slot count u32 | generation u32 per slot | free count u32 | free slots u32

#include <algorithm>
#include <cstring>

#include "math_util.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

constexpr std::uint32_t kMagic = 0x57504352;  // "RCPW"
/// 2: force fields, 3: projectiles, 4: configuration and dynamic sections, in-place restore.
constexpr std::uint32_t kVersion = 4;
constexpr std::size_t kHeaderBytes = 4 + 4 + 1 + 1 + 8 + 4;
/// Flags set by a body's definition (configuration) and by the simulation (dynamic state).
constexpr std::uint16_t kConfigFlags =
    kFlagKinematic | kFlagLockRotation | kFlagFast | kFlagSensor | kFlagAllowSleep;
constexpr std::uint16_t kStateFlags = kFlagSleeping | kFlagFrozen | kFlagExactVelocity;

/// Writes into a caller-owned buffer. Run once without a buffer to measure, then with one.
class Writer {
 public:
  explicit Writer(std::uint8_t* out = nullptr) : out_(out) {}
  template <class T>
  void pod(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (out_) std::memcpy(out_ + size_, &value, sizeof(T));
    size_ += sizeof(T);
  }
  void u8(bool value) { pod(static_cast<std::uint8_t>(value)); }
  void vec(const Vec3& v) { pod(v.x()), pod(v.y()), pod(v.z()); }
  void quat(const Quat& q) { pod(q.w()), pod(q.x()), pod(q.y()), pod(q.z()); }
  void pool(const SlotPool& p) {
    pod(p.slot_count());
    for (const std::uint32_t g : p.generation) pod(g);
    pod(static_cast<std::uint32_t>(p.free_slots.size()));
    for (const std::uint32_t s : p.free_slots) pod(s);
  }
  std::size_t size() const { return size_; }

 private:
  std::uint8_t* out_;
  std::size_t size_ = 0;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  /// Each read names its field, so a refusal says which one was wrong.
  template <class T>
  bool pod(T& value, const char* field) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (bytes_.size() - offset_ < sizeof(T)) return fail(field, "truncated");
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return true;
  }
  bool real(Real& value, const char* field) {
    return pod(value, field) && (is_finite(value) || fail(field, "not finite"));
  }
  bool vec(Vec3& v, const char* field) {
    return real(v.x(), field) && real(v.y(), field) && real(v.z(), field);
  }
  bool quat(Quat& q, const char* field) {
    return real(q.w(), field) && real(q.x(), field) && real(q.y(), field) && real(q.z(), field);
  }
  bool flag(bool& value, const char* field) {
    std::uint8_t byte = 0;
    if (!pod(byte, field)) return false;
    if (byte > 1) return fail(field, "not 0 or 1");
    value = byte != 0;
    return true;
  }
  /// A count that must be at most `limit` and fit in the remaining bytes at `min_size` each.
  bool count(std::uint32_t& n, std::uint32_t limit, std::size_t min_size, const char* field) {
    if (!pod(n, field)) return false;
    if (n > limit)
      return fail(
          field,
          ("is " + std::to_string(n) + ", above the limit " + std::to_string(limit)).c_str());
    if (static_cast<std::size_t>(n) * min_size > bytes_.size() - offset_)
      return fail(field, "exceeds the data");
    return true;
  }
  /// Reads a pool of at most `limit` slots and checks its free list.
  bool pool(SlotPool& p, std::uint32_t limit, std::vector<std::uint8_t>& seen, const char* field) {
    std::uint32_t slots = 0, free_count = 0;
    if (!count(slots, limit, 4, field)) return false;
    p.generation.resize(slots);
    for (std::uint32_t& g : p.generation) {
      if (!pod(g, field)) return false;
    }
    if (!count(free_count, slots, 4, field)) return false;
    p.free_slots.resize(free_count);
    for (std::uint32_t& s : p.free_slots) {
      if (!pod(s, field)) return false;
    }
    if (const std::string why = p.validate(seen); !why.empty()) return fail(field, why.c_str());
    return true;
  }
  bool fail(const char* field, const char* why) {
    if (error.empty())
      error = std::string(field) + ": " + why + " (at byte " + std::to_string(offset_) + ")";
    return false;
  }
  bool skip(std::size_t n) {
    if (bytes_.size() - offset_ < n) return fail("config", "truncated");
    offset_ += n;
    return true;
  }
  std::size_t offset() const { return offset_; }
  bool at_end() const { return offset_ == bytes_.size(); }
  std::string error;

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t offset_ = 0;
};

// --- configuration section ---

void write_config(Writer& out, const WorldState& s) {
  const BodyStore& b = s.bodies;
  out.pool(b.slots);
  for (std::uint32_t k = 0; k < b.slot_count(); ++k) {
    if (!b.alive(k)) continue;
    out.pod(static_cast<std::uint16_t>(b.flags[k] & kConfigFlags));
    out.pod(b.radius[k]), out.pod(b.mass_inverse_original[k]);
    out.pod(b.inertia_inverse_original[k]), out.pod(b.gravity_scale[k]);
    const Material& m = b.material[k];
    out.pod(m.restitution), out.pod(m.friction), out.pod(m.rolling_resistance);
    out.pod(b.filter[k].layer), out.pod(b.filter[k].mask), out.pod(b.user_data[k]);
  }
  out.pool(s.statics.slots());
  for (std::uint32_t k = 0; k < s.statics.slots().slot_count(); ++k) {
    if (!s.statics.alive(k)) continue;
    const StaticShape& shape = s.statics.shape(k);
    out.pod(static_cast<std::uint8_t>(shape.type));
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
  out.pool(s.forces.slots());
  for (std::uint32_t k = 0; k < s.forces.slots().slot_count(); ++k) {
    if (!s.forces.alive(k)) continue;
    const ForceField& f = s.forces.fields()[k];
    out.pod(static_cast<std::uint8_t>(f.kind)), out.pod(f.body), out.vec(f.point);
    out.pod(f.stiffness), out.pod(f.rest_length), out.pod(f.damping), out.pod(f.min_distance);
    out.pod(f.mask);
  }
}

bool material_ok(const Material& m) {
  return m.restitution >= 0 && m.restitution <= 1 && m.friction >= 0 && m.rolling_resistance >= 0;
}

bool unit(const Quat& q) {
  return std::abs(q.squaredNorm() - 1) <= Real(1e-3);
}

/// Reads the configuration into `next` (bodies' configuration fields, shapes, force fields),
/// checking each as the API that creates it would.
bool read_config(Reader& in, const WorldDef& def, WorldState& next,
                 std::vector<std::uint8_t>& seen) {
  BodyStore& b = next.bodies;
  if (!in.pool(b.slots, std::min(def.max_bodies, kMaxBodySlots), seen, "body pool")) return false;
  const std::uint32_t slots = b.slot_count();
  for (auto* v : {&b.position, &b.force, &b.torque}) v->assign(slots, Vec3::Zero());
  b.flags.assign(slots, 0);
  b.orientation.assign(slots, Quat::Identity());
  b.motion.assign(slots, Motion{});
  for (auto* v : {&b.radius, &b.mass_inverse_original, &b.inertia_inverse_original,
                  &b.gravity_scale, &b.sleep_time}) {
    v->assign(slots, 0);
  }
  b.material.assign(slots, Material{});
  b.filter.assign(slots, Filter{});
  b.user_data.assign(slots, 0);
  for (std::uint32_t k = 0; k < slots; ++k) {
    if (!b.alive(k)) continue;
    Material& m = b.material[k];
    if (!in.pod(b.flags[k], "body flags") || !in.real(b.radius[k], "body radius") ||
        !in.real(b.mass_inverse_original[k], "body inverse mass") ||
        !in.real(b.inertia_inverse_original[k], "body inverse inertia") ||
        !in.real(b.gravity_scale[k], "body gravity scale") ||
        !in.real(m.restitution, "body material") || !in.real(m.friction, "body material") ||
        !in.real(m.rolling_resistance, "body material") ||
        !in.pod(b.filter[k].layer, "body filter") || !in.pod(b.filter[k].mask, "body filter") ||
        !in.pod(b.user_data[k], "body user data")) {
      return false;
    }
    if ((b.flags[k] & ~kConfigFlags) != 0) return in.fail("body flags", "unknown flag bits");
    if (b.radius[k] <= 0) return in.fail("body radius", "not > 0");
    const bool kinematic = (b.flags[k] & kFlagKinematic) != 0;
    if (b.mass_inverse_original[k] < 0 || (kinematic && b.mass_inverse_original[k] != 0) ||
        (!kinematic && b.mass_inverse_original[k] == 0)) {
      return in.fail("body inverse mass", "negative, or not 0 exactly for kinematic bodies");
    }
    if (b.inertia_inverse_original[k] < 0) return in.fail("body inverse inertia", "negative");
    if (!material_ok(m)) return in.fail("body material", "out of range");
  }

  SlotPool shape_pool;
  if (!in.pool(shape_pool, std::min(def.max_shapes, kMaxShapeSlots), seen, "shape pool"))
    return false;
  std::vector<StaticShape> shapes(shape_pool.slot_count());
  for (std::uint32_t k = 0; k < shape_pool.slot_count(); ++k) {
    if (!shape_pool.alive(k)) continue;
    StaticShape& shape = shapes[k];
    std::uint8_t type = 0;
    std::uint32_t vertex_count = 0, index_count = 0;
    if (!in.pod(type, "shape type")) return false;
    if (type > static_cast<std::uint8_t>(ShapeType::Mesh)) return in.fail("shape type", "unknown");
    shape.type = static_cast<ShapeType>(type);
    if (!in.real(shape.material.restitution, "shape material") ||
        !in.real(shape.material.friction, "shape material") ||
        !in.real(shape.material.rolling_resistance, "shape material") ||
        !in.pod(shape.filter.layer, "shape filter") || !in.pod(shape.filter.mask, "shape filter") ||
        !in.vec(shape.plane_normal, "plane normal") ||
        !in.real(shape.plane_offset, "plane offset") || !in.vec(shape.box_center, "box centre") ||
        !in.quat(shape.box_orientation, "box orientation") ||
        !in.vec(shape.box_half_extents, "box half extents") ||
        !in.count(vertex_count, 3 * kMaxMeshTriangles, 3 * sizeof(Real), "mesh vertex count")) {
      return false;
    }
    if (!material_ok(shape.material)) return in.fail("shape material", "out of range");
    if (std::abs(shape.plane_normal.squaredNorm() - 1) > Real(1e-3))
      return in.fail("plane normal", "not unit");
    if (!unit(shape.box_orientation)) return in.fail("box orientation", "not unit");
    if (shape.box_half_extents.minCoeff() <= 0) return in.fail("box half extents", "not > 0");
    shape.vertices.resize(vertex_count);
    for (Vec3& v : shape.vertices) {
      if (!in.vec(v, "mesh vertex")) return false;
    }
    if (!in.count(index_count, 3 * kMaxMeshTriangles, 4, "mesh index count")) return false;
    if (index_count % 3 != 0) return in.fail("mesh index count", "not a multiple of 3");
    if ((shape.type == ShapeType::Mesh) != (index_count > 0))
      return in.fail("shape type / mesh index count",
                     "a mesh without triangles, or triangles on a plane or box");
    shape.indices.resize(index_count);
    for (std::uint32_t& i : shape.indices) {
      if (!in.pod(i, "mesh index")) return false;
      if (i >= vertex_count) return in.fail("mesh index", "not below the vertex count");
    }
  }

  SlotPool force_pool;
  if (!in.pool(force_pool, ForceFields::kMaxFields, seen, "force pool")) return false;
  std::vector<ForceField> fields(force_pool.slot_count());
  for (std::uint32_t k = 0; k < force_pool.slot_count(); ++k) {
    if (!force_pool.alive(k)) continue;
    ForceField& f = fields[k];
    std::uint8_t kind = 0;
    if (!in.pod(kind, "force kind")) return false;
    if (kind > static_cast<std::uint8_t>(ForceKind::Attractor))
      return in.fail("force kind", "unknown");
    f.kind = static_cast<ForceKind>(kind);
    if (!in.pod(f.body, "force body") || !in.vec(f.point, "force point") ||
        !in.real(f.stiffness, "force stiffness") || !in.real(f.rest_length, "force rest length") ||
        !in.real(f.damping, "force damping") || !in.real(f.min_distance, "force min distance") ||
        !in.pod(f.mask, "force mask")) {
      return false;
    }
    if (f.stiffness <= 0) return in.fail("force stiffness", "not > 0");
    if (f.rest_length < 0) return in.fail("force rest length", "negative");
    if (f.damping < 0) return in.fail("force damping", "negative");
    if (f.min_distance < 0) return in.fail("force min distance", "negative");
    if (f.kind == ForceKind::Spring &&
        (f.body >= slots || !b.alive(f.body) || b.has(f.body, kFlagKinematic))) {
      return in.fail("force kind / force body", "a spring on a missing or kinematic body");
    }
    if (f.kind == ForceKind::Attractor && f.min_distance <= 0)
      return in.fail("force kind / force min distance", "min distance not > 0 for an attractor");
  }
  next.statics.assign(std::move(shape_pool), std::move(shapes));
  next.forces.assign(std::move(force_pool), std::move(fields));
  return true;
}

// --- dynamic section ---

enum ContactBits : std::uint8_t {
  kContactTouching = 1 << 0,
  kContactFriction = 1 << 1,  ///< a friction impulse follows
  kContactRolling = 1 << 2,   ///< a rolling impulse follows
};

/// A contact the next step would treat like no contact at all: not touching, no impulse.
bool inert(const Contact& c) {
  return !c.touching && c.normal_impulse == 0 && c.friction_impulse == Vec3::Zero() &&
         c.rolling_impulse == Vec3::Zero();
}

void write_contacts(Writer& out, const std::vector<Contact>& contacts) {
  const auto kept =
      std::count_if(contacts.begin(), contacts.end(), [](const Contact& c) { return !inert(c); });
  out.pod(static_cast<std::uint32_t>(kept));
  for (const Contact& c : contacts) {
    if (inert(c)) continue;
    const bool friction = c.friction_impulse != Vec3::Zero();
    const bool rolling = c.rolling_impulse != Vec3::Zero();
    out.pod(c.key);
    out.pod(static_cast<std::uint8_t>((c.touching ? kContactTouching : 0) |
                                      (friction ? kContactFriction : 0) |
                                      (rolling ? kContactRolling : 0)));
    out.pod(c.normal_impulse);
    if (friction) out.vec(c.friction_impulse);
    if (rolling) out.vec(c.rolling_impulse);
  }
}

void write_dynamic(Writer& out, const WorldState& s) {
  out.pod(s.steps), out.vec(s.gravity);
  const BodyStore& b = s.bodies;
  std::uint32_t loaded = 0;
  for (std::uint32_t k = 0; k < b.slot_count(); ++k) {
    if (!b.alive(k)) continue;
    out.pod(static_cast<std::uint16_t>(b.flags[k] & kStateFlags));
    out.vec(b.position[k]), out.quat(b.orientation[k]);
    out.vec(b.motion[k].linear_velocity), out.vec(b.motion[k].angular_velocity);
    out.pod(b.sleep_time[k]);
    loaded += b.force[k] != Vec3::Zero() || b.torque[k] != Vec3::Zero() ? 1 : 0;
  }
  out.pod(loaded);
  for (std::uint32_t k = 0; k < b.slot_count() && loaded > 0; ++k) {
    if (!b.alive(k) || (b.force[k] == Vec3::Zero() && b.torque[k] == Vec3::Zero())) continue;
    out.pod(k), out.vec(b.force[k]), out.vec(b.torque[k]);
  }
  write_contacts(out, s.pair_contacts);
  write_contacts(out, s.static_contacts);
  out.pod(static_cast<std::uint32_t>(s.sensor_overlaps.size()));
  for (const std::uint64_t key : s.sensor_overlaps) out.pod(key);
  const ProjectileStore& p = s.projectiles;
  out.pool(p.slots);
  std::uint32_t previous = ~0u;
  for (std::uint32_t k = 0; k < p.slot_count(); ++k) {
    if (!p.alive(k)) continue;
    out.vec(p.position[k]), out.vec(p.velocity[k]);
    const bool same_shape = previous != ~0u && p.same_shape(k, previous);
    out.u8(same_shape);
    if (!same_shape) {
      out.pod(p.radius[k]), out.pod(p.gravity_scale[k]);
      out.pod(p.filter[k].layer), out.pod(p.filter[k].mask);
    }
    out.pod(p.ignore[k].index), out.pod(p.ignore[k].generation), out.pod(p.user_data[k]);
    previous = k;
  }
}

/// Reads contacts, deriving each one's body and shape slots from its key and checking that they
/// name live objects.
bool read_contacts(Reader& in, const BodyStore& b, const StaticGeometry& statics, bool pairs,
                   std::vector<Contact>& contacts) {
  const char* field = pairs ? "pair contact" : "static contact";
  std::uint32_t n = 0;
  if (!in.count(n, 1u << 28, 8 + 1 + sizeof(Real), field)) return false;
  contacts.resize(n);
  for (Contact& c : contacts) {
    c = Contact{};
    std::uint8_t bits = 0;
    if (!in.pod(c.key, field) || !in.pod(bits, field) || !in.real(c.normal_impulse, field))
      return false;
    if ((bits & ~(kContactTouching | kContactFriction | kContactRolling)) != 0)
      return in.fail(field, "unknown contact bits");
    c.touching = (bits & kContactTouching) != 0;
    if ((bits & kContactFriction) != 0 && !in.vec(c.friction_impulse, field)) return false;
    if ((bits & kContactRolling) != 0 && !in.vec(c.rolling_impulse, field)) return false;
    if (c.normal_impulse < 0) return in.fail(field, "negative normal impulse");
    if (pairs) {
      if ((c.key >> 63) != 0) return in.fail(field, "static key among pair contacts");
      c.a = static_cast<std::uint32_t>(c.key >> 32);
      c.b = static_cast<std::uint32_t>(c.key);
      if (c.a >= c.b || c.b >= b.slot_count() || !b.alive(c.a) || !b.alive(c.b))
        return in.fail(field, "key names a missing body or is not ordered a < b");
    } else {
      if ((c.key >> 63) == 0) return in.fail(field, "pair key among static contacts");
      c.a = static_cast<std::uint32_t>(c.key >> 41) & (kMaxBodySlots - 1);
      c.b = static_cast<std::uint32_t>(c.key >> 21) & (kMaxShapeSlots - 1);
      const std::uint32_t triangle = static_cast<std::uint32_t>(c.key) & (kMaxMeshTriangles - 1);
      if (c.a >= b.slot_count() || !b.alive(c.a) || c.b >= statics.slots().slot_count() ||
          !statics.alive(c.b)) {
        return in.fail(field, "key names a missing body or shape");
      }
      const StaticShape& shape = statics.shape(c.b);
      const std::size_t triangles = shape.type == ShapeType::Mesh ? shape.indices.size() / 3 : 1;
      if (triangle >= triangles) return in.fail(field, "key names a missing triangle");
    }
  }
  return true;
}

/// Reads the dynamic section into `out` (whose configuration fields are already in place),
/// checking every value against that configuration.
bool read_dynamic(Reader& in, const WorldDef& def, const WorldState& config, RestoreScratch& out) {
  const BodyStore& b = config.bodies;
  if (!in.pod(out.steps, "steps") || !in.vec(out.gravity, "gravity")) return false;
  const std::uint32_t slots = b.slot_count();
  out.flags.resize(slots);
  out.position.resize(slots);
  out.orientation.resize(slots);
  out.motion.resize(slots);
  out.force.assign(slots, Vec3::Zero());
  out.torque.assign(slots, Vec3::Zero());
  out.sleep_time.resize(slots);
  for (std::uint32_t k = 0; k < slots; ++k) {
    out.flags[k] = 0;
    out.motion[k] = Motion{};
    if (!b.alive(k)) continue;
    std::uint16_t flags = 0;
    Motion& m = out.motion[k];
    if (!in.pod(flags, "body state flags") || !in.vec(out.position[k], "body position") ||
        !in.quat(out.orientation[k], "body orientation") ||
        !in.vec(m.linear_velocity, "body linear velocity") ||
        !in.vec(m.angular_velocity, "body angular velocity") ||
        !in.real(out.sleep_time[k], "body sleep time")) {
      return false;
    }
    if ((flags & ~kStateFlags) != 0) return in.fail("body state flags", "unknown flag bits");
    if (!unit(out.orientation[k])) return in.fail("body orientation", "not unit");
    if (out.sleep_time[k] < 0) return in.fail("body sleep time", "negative");
    out.flags[k] = static_cast<std::uint16_t>(flags | (b.flags[k] & kConfigFlags));
    if ((flags & kFlagFrozen) != 0) {  // a frozen body is an obstacle: no velocity, no mass
      if (m.linear_velocity != Vec3::Zero() || m.angular_velocity != Vec3::Zero())
        return in.fail("body linear velocity", "not zero for a frozen body");
    } else {
      m.inverse_mass = b.mass_inverse_original[k];
      m.inverse_inertia = b.inertia_inverse_original[k];
    }
  }
  std::uint32_t loaded = 0;
  if (!in.count(loaded, slots, 4 + 6 * sizeof(Real), "body loads")) return false;
  std::uint32_t previous = 0;
  for (std::uint32_t n = 0; n < loaded; ++n) {
    std::uint32_t k = 0;
    if (!in.pod(k, "body load slot")) return false;
    if (k >= slots || !b.alive(k) || (n > 0 && k <= previous))
      return in.fail("body load slot", "names a missing body or is out of order");
    previous = k;
    if (!in.vec(out.force[k], "body force") || !in.vec(out.torque[k], "body torque")) return false;
  }
  if (!read_contacts(in, b, config.statics, true, out.pair_contacts) ||
      !read_contacts(in, b, config.statics, false, out.static_contacts)) {
    return false;
  }
  std::uint32_t overlaps = 0;
  if (!in.count(overlaps, 1u << 28, 8, "sensor overlap")) return false;
  out.sensor_overlaps.resize(overlaps);
  for (std::uint32_t n = 0; n < overlaps; ++n) {
    std::uint64_t& key = out.sensor_overlaps[n];
    if (!in.pod(key, "sensor overlap")) return false;
    const auto first = static_cast<std::uint32_t>(key >> 32),
               second = static_cast<std::uint32_t>(key);
    if (first >= second || second >= slots || !b.alive(first) || !b.alive(second))
      return in.fail("sensor overlap", "key names a missing body or is not ordered a < b");
    if (!b.has(first, kFlagSensor) && !b.has(second, kFlagSensor))
      return in.fail("sensor overlap", "key names two bodies neither of which is a sensor");
    if (n > 0 && key <= out.sensor_overlaps[n - 1])
      return in.fail("sensor overlap", "keys not strictly ascending");
  }
  ProjectileStore& p = out.projectiles;
  if (!in.pool(p.slots, std::min(def.max_projectiles, kMaxProjectileSlots), out.seen,
               "projectile pool")) {
    return false;
  }
  p.resize(p.slot_count());
  std::uint32_t previous_live = ~0u;
  for (std::uint32_t k = 0; k < p.slot_count(); ++k) {
    if (!p.alive(k)) continue;
    bool same_shape = false;
    if (!in.vec(p.position[k], "projectile position") ||
        !in.vec(p.velocity[k], "projectile velocity") ||
        !in.flag(same_shape, "projectile shape bit")) {
      return false;
    }
    if (same_shape) {
      if (previous_live == ~0u)
        return in.fail("projectile shape bit", "set on the first live projectile");
      p.copy_shape(k, previous_live);
    } else if (!in.real(p.radius[k], "projectile radius") ||
               !in.real(p.gravity_scale[k], "projectile gravity scale") ||
               !in.pod(p.filter[k].layer, "projectile filter") ||
               !in.pod(p.filter[k].mask, "projectile filter")) {
      return false;
    }
    previous_live = k;
    if (!in.pod(p.ignore[k].index, "projectile ignore") ||
        !in.pod(p.ignore[k].generation, "projectile ignore") ||
        !in.pod(p.user_data[k], "projectile user data")) {
      return false;
    }
    if (p.radius[k] < 0) return in.fail("projectile radius", "negative");
    if (p.velocity[k].norm() > def.max_linear_speed)
      return in.fail("projectile velocity", "above max_linear_speed");
  }
  return true;
}

/// Swaps what read_dynamic read into the world's state (the old buffers become scratch).
void commit_dynamic(RestoreScratch& in, WorldState& s) {
  BodyStore& b = s.bodies;
  std::swap(b.flags, in.flags);
  std::swap(b.position, in.position);
  std::swap(b.orientation, in.orientation);
  std::swap(b.motion, in.motion);
  std::swap(b.force, in.force);
  std::swap(b.torque, in.torque);
  std::swap(b.sleep_time, in.sleep_time);
  std::swap(s.pair_contacts, in.pair_contacts);
  std::swap(s.static_contacts, in.static_contacts);
  std::swap(s.sensor_overlaps, in.sensor_overlaps);
  std::swap(s.projectiles, in.projectiles);
  s.steps = in.steps;
  s.gravity = in.gravity;
}

// A new field in one of these must be written by write_config or write_dynamic and read back by
// read_config or read_dynamic (or be derived there); then update the size here. The save image
// is then complete, and state_hash, which hashes the image, covers the new field too.
static_assert(sizeof(WorldState) == sizeof(BodyStore) + sizeof(StaticGeometry) +
                                        sizeof(ForceFields) + sizeof(ProjectileStore) + 8 +
                                        sizeof(Vec3) + 3 * sizeof(std::vector<int>) +
                                        (sizeof(Vec3) % 8 == 0 ? 0 : 8 - sizeof(Vec3) % 8));
static_assert(sizeof(BodyStore) == sizeof(SlotPool) + 14 * sizeof(std::vector<int>));
static_assert(sizeof(ProjectileStore) == sizeof(SlotPool) + 7 * sizeof(std::vector<int>));
static_assert(sizeof(SlotPool) == 2 * sizeof(std::vector<int>) + 8);
// Shapes and fields, plus lists, primitive boxes and a hierarchy rebuilt from them by assign().
static_assert(sizeof(StaticGeometry) == sizeof(SlotPool) + 5 * sizeof(std::vector<int>));
static_assert(sizeof(ForceFields) == sizeof(SlotPool) + 3 * sizeof(std::vector<int>));

}  // namespace

std::uint64_t WorldImpl::config_fingerprint() const {
  if (fingerprint_version != config_version) {
    Writer measure;
    write_config(measure, state);
    image_scratch.resize(measure.size());
    Writer out(image_scratch.data());
    write_config(out, state);
    Fnv1a h;
    h.add(image_scratch.data(), image_scratch.size());
    fingerprint = h.value();
    fingerprint_version = config_version;
  }
  return fingerprint;
}

void WorldImpl::save(std::vector<std::uint8_t>& image, StateParts parts) const {
  const bool with_config = parts == StateParts::All;
  const std::uint64_t print = config_fingerprint();
  Writer measure;
  if (with_config) write_config(measure, state);
  const std::size_t config_bytes = measure.size();
  write_dynamic(measure, state);
  image.resize(kHeaderBytes + measure.size());
  Writer out(image.data());
  out.pod(kMagic), out.pod(kVersion), out.pod(static_cast<std::uint8_t>(sizeof(Real)));
  out.u8(with_config), out.pod(print), out.pod(static_cast<std::uint32_t>(config_bytes));
  if (with_config) write_config(out, state);
  write_dynamic(out, state);
}

Status WorldImpl::restore(std::span<const std::uint8_t> bytes) {
  Reader in(bytes);
  const auto corrupt = [&](const std::string& why) {
    return Status(Error{ErrorCode::CorruptState, "restore_state: " + why});
  };
  std::uint32_t magic = 0, version = 0, config_bytes = 0;
  std::uint8_t real_size = 0;
  bool with_config = false;
  std::uint64_t print = 0;
  if (!in.pod(magic, "magic") || magic != kMagic)
    return corrupt("magic: not a Ricochet physics state");
  if (!in.pod(version, "version") || version != kVersion) {
    return corrupt("version: state version " + std::to_string(version) + ", this build reads " +
                   std::to_string(kVersion));
  }
  if (!in.pod(real_size, "real size") || real_size != sizeof(Real)) {
    return corrupt("real size: state saved with " + std::to_string(real_size * 8) +
                   "-bit reals, this build uses " + std::to_string(sizeof(Real) * 8));
  }
  if (!in.flag(with_config, "has config") || !in.pod(print, "fingerprint") ||
      !in.pod(config_bytes, "config bytes")) {
    return corrupt(in.error);
  }
  if (!with_config && config_bytes != 0)
    return corrupt("has config: 0, but config bytes is " + std::to_string(config_bytes));

  if (print == config_fingerprint()) {  // same configuration: restore in place
    if (!in.skip(config_bytes) || !read_dynamic(in, def, state, restore_scratch))
      return corrupt(in.error);
    if (!in.at_end()) return corrupt("trailing bytes after the state");
    commit_dynamic(restore_scratch, state);
  } else {
    if (!with_config) {
      return corrupt(
          "the image holds only the dynamic state of another configuration "
          "(bodies, shapes or force fields differ); restore a StateParts::All image");
    }
    if (bytes.size() - in.offset() < config_bytes) return corrupt("config bytes: truncated");
    Fnv1a config_hash;
    config_hash.add(bytes.data() + in.offset(), config_bytes);
    if (config_hash.value() != print)
      return corrupt("fingerprint: does not match the configuration section");
    WorldState next;
    const std::size_t config_start = in.offset();
    if (!read_config(in, def, next, restore_scratch.seen)) return corrupt(in.error);
    if (in.offset() - config_start != config_bytes)
      return corrupt("config bytes: " + std::to_string(config_bytes) + " announced, " +
                     std::to_string(in.offset() - config_start) + " read");
    if (!read_dynamic(in, def, next, restore_scratch)) return corrupt(in.error);
    if (!in.at_end()) return corrupt("trailing bytes after the state");
    commit_dynamic(restore_scratch, next);
    state = std::move(next);
    ++config_version;
  }
  def.gravity = state.gravity;
  // Last step's events belong to the abandoned timeline; every body is where the image puts it,
  // so the next step reports each as moved (snapshot building resends them all).
  events.clear_step();
  events.pending_end_events.clear();
  for (const std::uint32_t s : events.marked_slots) events.move_marks[s] = 0;
  events.marked_slots.clear();
  for (std::uint32_t s = 0; s < state.bodies.slot_count(); ++s) {
    if (state.bodies.alive(s)) mark_for_move_event(s, kMoveMarkMoved);
  }
  query_grid.mark_stale();
  return {};
}

std::uint64_t World::state_hash() const {
  impl_->save(impl_->image_scratch_hash, StateParts::Dynamic);
  Fnv1a h;
  h.add(impl_->image_scratch_hash.data(), impl_->image_scratch_hash.size());
  return h.value();
}

void World::save_state(std::vector<std::uint8_t>& image, StateParts parts) const {
  impl_->save(image, parts);
}

std::vector<std::uint8_t> World::save_state() const {
  std::vector<std::uint8_t> image;
  impl_->save(image, StateParts::All);
  return image;
}

Status World::restore_state(std::span<const std::uint8_t> bytes) {
  return impl_->restore(bytes);
}

}  // namespace ricochet::physics
