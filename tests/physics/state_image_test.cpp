// The state image, field by field. The test walks a valid image with its own reading of the
// layout documented in physics/src/state_io.cpp, then corrupts every field in turn (out of range,
// wrong order, dead index, NaN and infinities, flipped flag bits) and asserts that restore_state
// either refuses with CorruptState and a message naming the field, or gives a world whose next
// 120 steps stay finite (run under ASan/UBSan in the sanitizer build). It also checks that the
// image is complete: restoring any image and saving again gives back the same bytes.

#include <cstring>
#include <functional>

#include "test_util.h"

namespace ricochet::physics::test::state_image_test {
namespace {

constexpr std::size_t kReal = sizeof(Real);

enum class Kind { U8, U16, U32, U64, Real };
/// What a field means, which decides how it is corrupted.
enum class Role {
  Value,
  Flags,
  Count,
  Generation,
  FreeSlot,
  BodySlot,
  PairKey,
  StaticKey,
  SensorKey
};

struct Field {
  std::size_t offset;
  Kind kind;
  Role role;
  std::string name;  ///< as the refusal names it
  bool config;       ///< in the configuration section (the fingerprint covers it)
};

std::size_t size_of(Kind k) {
  switch (k) {
    case Kind::U8:
      return 1;
    case Kind::U16:
      return 2;
    case Kind::U32:
      return 4;
    case Kind::U64:
      return 8;
    case Kind::Real:
      return kReal;
  }
  return 0;
}

/// Walks a StateParts::All image and lists its fields.
class ImageMap {
 public:
  explicit ImageMap(const std::vector<std::uint8_t>& image) : image_(image) {
    take(Kind::U32, Role::Value, "magic");
    take(Kind::U32, Role::Value, "version");
    take(Kind::U8, Role::Value, "real size");
    take(Kind::U8, Role::Value, "has config");
    fingerprint_offset = offset_;
    take(Kind::U64, Role::Value, "fingerprint");
    take(Kind::U32, Role::Count, "config bytes");
    config_start = offset_;
    config_ = true;
    const std::vector<bool> bodies = pool("body pool");
    body_slots = static_cast<std::uint32_t>(bodies.size());
    for (std::uint32_t k = 0; k < bodies.size(); ++k) {
      if (!bodies[k]) {
        dead_body = k;
        continue;
      }
      live_bodies.push_back(k);
      take(Kind::U16, Role::Flags, "body flags");
      take(Kind::Real, Role::Value, "body radius");
      take(Kind::Real, Role::Value, "body inverse mass");
      take(Kind::Real, Role::Value, "body inverse inertia");
      take(Kind::Real, Role::Value, "body gravity scale");
      reals(3, "body material");
      take(Kind::U32, Role::Value, "body filter");
      take(Kind::U32, Role::Value, "body filter");
      take(Kind::U64, Role::Value, "body user data");
    }
    for (const bool live : pool("shape pool")) {
      if (!live) continue;
      const std::uint8_t type = image_[offset_];
      take(Kind::U8, Role::Value, "shape type");
      reals(3, "shape material");
      take(Kind::U32, Role::Value, "shape filter");
      take(Kind::U32, Role::Value, "shape filter");
      reals(3, "plane normal");
      reals(1, "plane offset");
      reals(3, "box centre");
      reals(4, "box orientation");
      reals(3, "box half extents");
      const std::uint32_t vertices = take(Kind::U32, Role::Count, "mesh vertex count");
      reals(3 * vertices, "mesh vertex");
      const std::uint32_t indices = take(Kind::U32, Role::Count, "mesh index count");
      for (std::uint32_t i = 0; i < indices; ++i) take(Kind::U32, Role::Value, "mesh index");
      (void)type;
    }
    for (const bool live : pool("force pool")) {
      if (!live) continue;
      take(Kind::U8, Role::Value, "force kind");
      take(Kind::U32, Role::BodySlot, "force body");
      reals(3, "force point");
      reals(1, "force stiffness");
      reals(1, "force rest length");
      reals(1, "force damping");
      reals(1, "force min distance");
      take(Kind::U32, Role::Value, "force mask");
    }
    config_end = offset_;
    config_ = false;
    take(Kind::U64, Role::Value, "steps");
    reals(3, "gravity");
    for (std::size_t k = 0; k < live_bodies.size(); ++k) {
      take(Kind::U16, Role::Flags, "body state flags");
      reals(3, "body position");
      reals(4, "body orientation");
      reals(3, "body linear velocity");
      reals(3, "body angular velocity");
      reals(1, "body sleep time");
    }
    const std::uint32_t loads = take(Kind::U32, Role::Count, "body loads");
    for (std::uint32_t n = 0; n < loads; ++n) {
      take(Kind::U32, Role::BodySlot, "body load slot");
      reals(3, "body force");
      reals(3, "body torque");
    }
    for (const char* list : {"pair contact", "static contact"}) {
      const bool pairs = std::strcmp(list, "pair contact") == 0;
      const std::uint32_t n = take(Kind::U32, Role::Count, list);
      for (std::uint32_t c = 0; c < n; ++c) {
        take(Kind::U64, pairs ? Role::PairKey : Role::StaticKey, list);
        const auto bits = take(Kind::U8, Role::Count, list);  // which impulses follow
        reals(1 + ((bits & 2) ? 3 : 0) + ((bits & 4) ? 3 : 0), list);
      }
    }
    const std::uint32_t overlaps = take(Kind::U32, Role::Count, "sensor overlap");
    for (std::uint32_t n = 0; n < overlaps; ++n) take(Kind::U64, Role::SensorKey, "sensor overlap");
    for (const bool live : pool("projectile pool")) {
      if (!live) continue;
      reals(3, "projectile position");
      reals(3, "projectile velocity");
      if (take(Kind::U8, Role::Count, "projectile shape bit") == 0) {
        reals(1, "projectile radius");
        reals(1, "projectile gravity scale");
        take(Kind::U32, Role::Value, "projectile filter");
        take(Kind::U32, Role::Value, "projectile filter");
      }
      take(Kind::U32, Role::Value, "projectile ignore");
      take(Kind::U32, Role::Value, "projectile ignore");
      take(Kind::U64, Role::Value, "projectile user data");
    }
    complete = offset_ == image_.size();
  }

  std::vector<Field> fields;
  std::size_t fingerprint_offset = 0, config_start = 0, config_end = 0;
  std::vector<std::uint32_t> live_bodies;
  std::uint32_t body_slots = 0;
  std::uint32_t dead_body = ~0u;
  bool complete = false;

 private:
  std::uint64_t take(Kind kind, Role role, const std::string& name) {
    std::uint64_t value = 0;
    if (offset_ + size_of(kind) > image_.size()) return 0;
    std::memcpy(&value, image_.data() + offset_, size_of(kind));
    fields.push_back({offset_, kind, role, name, config_});
    offset_ += size_of(kind);
    return value;
  }
  void reals(std::uint32_t n, const std::string& name) {
    for (std::uint32_t i = 0; i < n; ++i) take(Kind::Real, Role::Value, name);
  }
  /// Slot count, generations and free list; returns which slots are alive (odd generation).
  std::vector<bool> pool(const std::string& name) {
    const auto slots = static_cast<std::uint32_t>(take(Kind::U32, Role::Count, name));
    std::vector<bool> live(slots);
    for (std::uint32_t k = 0; k < slots; ++k)
      live[k] = (take(Kind::U32, Role::Generation, name) & 1) != 0;
    const auto free_count = static_cast<std::uint32_t>(take(Kind::U32, Role::Count, name));
    for (std::uint32_t k = 0; k < free_count; ++k) take(Kind::U32, Role::FreeSlot, name);
    return live;
  }

  const std::vector<std::uint8_t>& image_;
  std::size_t offset_ = 0;
  bool config_ = false;
};

std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= data[i];
    h *= 1099511628211ull;
  }
  return h;
}

/// A world with every section filled: a plane, a box and a mesh; resting and stacked spheres, a
/// kinematic body, a sensor overlapping a sphere, a dead body slot, a spring and an attractor, a
/// force applied since the last step, a live and a dead projectile.
World rich_world() {
  World world = make_world(WorldDef{});
  add_floor(world);
  add_box(world, Vec3(3, Real(0.5), 0), Vec3::Constant(Real(0.5)));
  add_mesh(world, {Vec3(-4, 0, -1), Vec3(-2, 0, -1), Vec3(-3, 1, 1)}, {0, 1, 2});
  const BodyId low = add_sphere(world, Vec3(0, Real(0.5), 0));
  add_sphere(world, Vec3(0, Real(1.5), 0));
  const BodyId gone = add_sphere(world, Vec3(5, 3, 5));
  const BodyId sprung = add_sphere(world, Vec3(-1, 2, 2), Real(0.3));
  BodyDef kinematic = sphere_def(Vec3(1, 3, 0));
  kinematic.type = BodyType::Kinematic;
  kinematic.linear_velocity = Vec3(Real(0.1), 0, 0);
  add_body(world, kinematic);
  BodyDef sensor = sphere_def(Vec3(0, Real(0.5), Real(0.6)), Real(0.4));
  sensor.sensor = true;
  sensor.gravity_scale = 0;
  add_body(world, sensor);
  RICOCHET_EXPECT_OK(world.destroy_body(gone));
  unwrap(world.add_spring({.body = sprung,
                           .anchor = Vec3(-1, 3, 2),
                           .stiffness = 50,
                           .rest_length = Real(0.5),
                           .damping = 1}),
         "add_spring");
  unwrap(world.add_attractor({.center = Vec3(0, 20, 0), .strength = 1}), "add_attractor");
  ProjectileDef shot;
  shot.position = Vec3(-3, 4, 0);
  shot.velocity = Vec3(2, 0, 0);
  shot.gravity_scale = 0;
  shot.radius = Real(0.02);
  unwrap(world.create_projectile(shot), "create_projectile");
  shot.position.y() += 1;
  unwrap(world.create_projectile(shot), "create_projectile");  // same shape: one bit
  shot.radius = Real(0.05);
  unwrap(world.create_projectile(shot), "create_projectile");
  const ProjectileId spent = unwrap(world.create_projectile(shot), "create_projectile");
  RICOCHET_EXPECT_OK(world.destroy_projectile(spent));
  EXPECT_TRUE(run(world, 40));
  RICOCHET_EXPECT_OK(world.apply_force(low, Vec3(1, 0, 0)));
  RICOCHET_EXPECT_OK(world.apply_torque(low, Vec3(0, 1, 0)));
  return world;
}

template <class T>
void put(std::vector<std::uint8_t>& image, std::size_t offset, T value) {
  std::memcpy(image.data() + offset, &value, sizeof value);
}
template <class T>
T get(const std::vector<std::uint8_t>& image, std::size_t offset) {
  T value;
  std::memcpy(&value, image.data() + offset, sizeof value);
  return value;
}

/// The corrupted versions of one field.
std::vector<std::vector<std::uint8_t>> corruptions(const std::vector<std::uint8_t>& image,
                                                   const ImageMap& map, std::size_t index) {
  const Field& f = map.fields[index];
  std::vector<std::vector<std::uint8_t>> out;
  const auto with = [&](auto value) {
    std::vector<std::uint8_t> bad = image;
    put(bad, f.offset, value);
    out.push_back(std::move(bad));
  };
  switch (f.kind) {
    case Kind::Real:
      for (const Real r :
           {std::numeric_limits<Real>::quiet_NaN(), std::numeric_limits<Real>::infinity(),
            -std::numeric_limits<Real>::infinity(), Real(-1), Real(0), Real(1e30)}) {
        with(r);
      }
      break;
    case Kind::U8:
      with(std::uint8_t{2}), with(std::uint8_t{0xFF}),
          with(static_cast<std::uint8_t>(get<std::uint8_t>(image, f.offset) ^ 1));
      break;
    case Kind::U16:
      for (int bit = 0; bit < 16; ++bit)
        with(static_cast<std::uint16_t>(get<std::uint16_t>(image, f.offset) ^ (1u << bit)));
      break;
    case Kind::U32: {
      const auto v = get<std::uint32_t>(image, f.offset);
      with(std::uint32_t{0}), with(~std::uint32_t{0}), with(v + 1), with(v - 1);
      if (f.role == Role::BodySlot || f.role == Role::FreeSlot) {
        with(map.dead_body), with(map.body_slots);
      }
      break;
    }
    case Kind::U64: {
      const auto v = get<std::uint64_t>(image, f.offset);
      with(~std::uint64_t{0}), with(v + 1), with(v ^ (1ull << 63));
      if (f.role == Role::PairKey || f.role == Role::SensorKey) {
        const auto a = static_cast<std::uint32_t>(v >> 32), b = static_cast<std::uint32_t>(v);
        with((std::uint64_t{b} << 32) | a);               // wrong order: a > b
        with((std::uint64_t{a} << 32) | map.dead_body);   // dead index
        with((std::uint64_t{map.dead_body} << 32) | b);   // dead index
        with((std::uint64_t{a} << 32) | map.body_slots);  // out of range
      }
      if (f.role == Role::StaticKey) {
        with((v & ~(0x3FFFFFull << 41)) | (std::uint64_t{map.dead_body} << 41));  // dead body
        with(v | (0xFFFFFull << 21));                                             // missing shape
        with(v | 0x1FFFFFull);  // missing triangle
      }
      break;
    }
  }
  // A forged configuration carries a matching fingerprint, so the fields themselves are checked.
  if (f.config) {
    for (std::vector<std::uint8_t>& bad : out) {
      put(bad, map.fingerprint_offset,
          fnv1a(bad.data() + map.config_start, map.config_end - map.config_start));
    }
  }
  return out;
}

/// Restores `bad` into `target`; either a refusal naming the field, or 120 clean steps.
::testing::AssertionResult refused_or_runs_clean(World& target,
                                                 const std::vector<std::uint8_t>& bad,
                                                 const Field& f, int& refused) {
  const Status status = target.restore_state(bad);
  if (!status) {
    ++refused;
    if (status.error().code != ErrorCode::CorruptState)
      return ::testing::AssertionFailure() << "wrong code: " << status.error().message;
    const bool named = f.role == Role::Count || f.role == Role::Flags ||
                       status.error().message.find(f.name) != std::string::npos;
    if (!named)
      return ::testing::AssertionFailure()
             << "refusal does not name the field: " << status.error().message;
    return ::testing::AssertionSuccess();
  }
  for (int i = 0; i < 120; ++i) {
    if (Status s = target.step(Real(1) / 60); !s)
      return ::testing::AssertionFailure() << "step failed: " << s.error().message;
  }
  const std::vector<std::uint8_t> image = target.save_state();
  World copy = make_world(WorldDef{});
  if (Status s = copy.restore_state(image); !s)
    return ::testing::AssertionFailure()
           << "accepted state does not round-trip: " << s.error().message;
  if (copy.state_hash() != target.state_hash())
    return ::testing::AssertionFailure() << "accepted state's round trip changes the hash";
  return ::testing::AssertionSuccess();
}

/// Corrupts every field of `image` and restores each version into a world from make_target().
void corrupt_every_field(const std::vector<std::uint8_t>& image, const ImageMap& map,
                         std::size_t skip_bytes, const std::function<World()>& make_target) {
  World target = make_target();
  const std::vector<std::uint8_t> clean = target.save_state();
  int tried = 0, refused = 0;
  for (std::size_t k = 0; k < map.fields.size(); ++k) {
    const Field& f = map.fields[k];
    if (skip_bytes > 0 && f.config) continue;  // a Dynamic image has no configuration
    for (std::vector<std::uint8_t> bad : corruptions(image, map, k)) {
      if (skip_bytes > 0) {  // cut the configuration out: a Dynamic image
        bad.erase(bad.begin() + static_cast<std::ptrdiff_t>(map.config_start),
                  bad.begin() + static_cast<std::ptrdiff_t>(map.config_end));
        bad[9] = 0;                                 // has config
        put(bad, 18, std::uint32_t{0});             // config bytes
        if (f.offset < map.config_start) continue;  // header fields: see the All pass
      }
      ++tried;
      EXPECT_TRUE(refused_or_runs_clean(target, bad, f, refused))
          << f.name << " at byte " << f.offset << " (corruption " << tried << ")";
      RICOCHET_ASSERT_OK(target.restore_state(clean));
    }
  }
  std::printf("[          ] %d corrupted images, %d refused, %d ran 120 clean steps\n", tried,
              refused, tried - refused);
  EXPECT_GT(refused, tried / 4) << "suspiciously few refusals";
}

TEST(StateImage, TheTestReadsTheDocumentedLayout) {
  const World world = rich_world();
  const std::vector<std::uint8_t> image = world.save_state();
  const ImageMap map(image);
  ASSERT_TRUE(map.complete) << "the image does not follow the layout documented in state_io.cpp";
  EXPECT_EQ(get<std::uint32_t>(image, 18), map.config_end - map.config_start);
  EXPECT_EQ(get<std::uint64_t>(image, map.fingerprint_offset),
            fnv1a(image.data() + map.config_start, map.config_end - map.config_start));
  // Every section is filled, so every field kind is corrupted below.
  for (const char* name : {"body load slot", "pair contact", "static contact", "sensor overlap",
                           "force body", "mesh index", "projectile position"}) {
    EXPECT_TRUE(std::any_of(map.fields.begin(), map.fields.end(),
                            [&](const Field& f) { return f.name == name; }))
        << "no " << name << " in the image";
  }
  EXPECT_NE(map.dead_body, ~0u);
}

TEST(StateImage, EveryCorruptFieldOfAFullImageIsRefusedOrHarmless) {
  const World world = rich_world();
  const std::vector<std::uint8_t> image = world.save_state();
  const ImageMap map(image);
  ASSERT_TRUE(map.complete);
  // Into an empty world: the configuration differs, so it is read and checked.
  corrupt_every_field(image, map, 0, [] { return make_world(WorldDef{}); });
}

TEST(StateImage, EveryCorruptFieldOfADynamicImageIsRefusedOrHarmless) {
  World world = rich_world();
  const std::vector<std::uint8_t> full = world.save_state();
  const ImageMap map(full);
  ASSERT_TRUE(map.complete);
  std::vector<std::uint8_t> dynamic;
  world.save_state(dynamic, StateParts::Dynamic);
  ASSERT_EQ(dynamic.size(), full.size() - (map.config_end - map.config_start));
  // Into the same world a few steps on: same configuration, so it restores in place.
  corrupt_every_field(full, map, map.config_end - map.config_start, [] {
    World target = rich_world();
    EXPECT_TRUE(run(target, 7));
    return target;
  });
}

TEST(StateImage, RestoringAndSavingAgainGivesTheSameBytes) {
  // Every field read back is kept: an image field that restore_state dropped would change the
  // second save.
  World world = rich_world();
  for (const StateParts parts : {StateParts::All, StateParts::Dynamic}) {
    std::vector<std::uint8_t> image, again;
    world.save_state(image, parts);
    World target = parts == StateParts::All ? make_world(WorldDef{}) : rich_world();
    if (parts == StateParts::Dynamic) {
      EXPECT_TRUE(run(target, 3));
    }
    RICOCHET_ASSERT_OK(target.restore_state(image));
    target.save_state(again, parts);
    EXPECT_EQ(again, image) << (parts == StateParts::All ? "All" : "Dynamic");
    EXPECT_EQ(target.state_hash(), world.state_hash());
  }
}

TEST(StateImage, ADynamicImageNeedsItsConfiguration) {
  World world = rich_world();
  std::vector<std::uint8_t> dynamic;
  world.save_state(dynamic, StateParts::Dynamic);
  World other = make_world(WorldDef{});
  add_floor(other);
  const WorldSnapshot before = snapshot(other);
  const Status status = other.restore_state(dynamic);
  EXPECT_TRUE(fails_with(status, ErrorCode::CorruptState));
  EXPECT_NE(status.error().message.find("another configuration"), std::string::npos)
      << status.error().message;
  EXPECT_TRUE(unchanged(other, before));
  // After a body is created the configuration differs too.
  add_sphere(world, Vec3(0, 9, 0));
  EXPECT_TRUE(fails_with(world.restore_state(dynamic), ErrorCode::CorruptState));
}

TEST(StateImage, ADynamicImageIsSmallAndRewindsExactly) {
  World world = rich_world();
  std::vector<std::uint8_t> image;
  world.save_state(image, StateParts::Dynamic);
  const std::uint64_t at_save = world.state_hash();
  ASSERT_TRUE(run(world, 30));
  const std::uint64_t later = world.state_hash();
  RICOCHET_ASSERT_OK(world.restore_state(image));
  EXPECT_EQ(world.state_hash(), at_save);
  ASSERT_TRUE(run(world, 30));
  EXPECT_EQ(world.state_hash(), later) << "replay after an in-place rewind diverged";
  // 5 live bodies at 2 bytes + 16 reals, 3 projectiles at 6 reals + 1 + 16 (+ 2 reals and 8 for
  // the two that do not share a shape), pools, header, loads and contacts (at most 17 + 7 reals
  // each, touching ones only) add the rest.
  EXPECT_LT(image.size(), 5 * (2 + 16 * kReal) + 3 * (6 * kReal + 17) + 2 * (2 * kReal + 8) + 600);
}

}  // namespace
}  // namespace ricochet::physics::test::state_image_test
