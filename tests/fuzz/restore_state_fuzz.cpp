// libFuzzer target for World::restore_state: any bytes are either refused with CorruptState,
// leaving the world unchanged, or restored into a world that then steps 120 times at 60 Hz with
// every body finite, and whose save_state images restore to the same state_hash. Every other
// outcome, and every sanitizer report, is a bug in physics/. Run it with tools/fuzz.sh.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <vector>

#include "fuzz_world.h"

namespace {

using namespace ricochet::physics;
using fuzz::kDt;
using fuzz::make_fuzz_world;

constexpr int kSteps = 120;

// The image header (physics/src/state_io.cpp): magic u32 | version u32 | sizeof(Real) u8 |
// has_config u8 | fingerprint u64 | config bytes u32. The configuration that follows begins with
// the body pool: slot count u32 | generation u32 per slot (odd while alive) | ...
constexpr std::size_t kHasConfigAt = 9;
constexpr std::size_t kFingerprintAt = 10;
constexpr std::size_t kConfigBytesAt = 18;
constexpr std::size_t kHeaderBytes = 22;

template <class T>
T load(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof value);
  return value;
}

void check(bool ok, const char* what, const char* detail = "") {
  if (ok) return;
  std::fprintf(stderr, "restore_state_fuzz: %s %s\n", what, detail);
  __builtin_trap();
}

/// Every live body's handle, read from the body pool of the world's own StateParts::All image
/// (the public API has no body iterator).
std::vector<BodyId> live_bodies(const World& world) {
  const std::vector<std::uint8_t> image = world.save_state();
  check(image.size() >= kHeaderBytes + 4, "save_state: image shorter than its header");
  const std::uint32_t slots = load<std::uint32_t>(image.data() + kHeaderBytes);
  check(image.size() >= kHeaderBytes + 4 + 4 * std::size_t{slots}, "save_state: body pool cut");
  std::vector<BodyId> ids;
  for (std::uint32_t k = 0; k < slots; ++k) {
    const auto generation = load<std::uint32_t>(image.data() + kHeaderBytes + 4 + 4 * k);
    if ((generation & 1u) != 0) ids.push_back(BodyId{k, generation});
  }
  check(ids.size() == world.body_count(), "body pool disagrees with body_count()");
  return ids;
}

void check_bodies_finite(const World& world, const std::vector<BodyId>& ids) {
  for (const BodyId id : ids) {
    const Result<BodyState> state = world.body_state(id);
    check(state.ok(), "body_state failed for a live body");
    const BodyState& s = state.value();
    check(s.position.allFinite() && s.orientation.coeffs().allFinite() &&
              s.linear_velocity.allFinite() && s.angular_velocity.allFinite(),
          "a body's state is not finite");
  }
}

/// save_state → restore_state: the All image into an empty world, and the Dynamic image in place,
/// both give back the same state_hash (and the copy saves the same bytes). Returns the copy.
World check_round_trip(World& world, const char* when) {
  const std::uint64_t hash = world.state_hash();
  std::vector<std::uint8_t> all, dynamic, again;
  world.save_state(all, StateParts::All);
  world.save_state(dynamic, StateParts::Dynamic);

  World copy = fuzz::must(World::create(fuzz::fuzz_world_def()), "World::create");
  const Status restored = copy.restore_state(all);
  check(restored.ok(), when, restored.ok() ? "" : restored.error().message.c_str());
  check(copy.state_hash() == hash, when, "the All image restores to another state_hash");
  copy.save_state(again, StateParts::All);
  check(again == all, when, "the All image restores to a world that saves other bytes");

  const Status in_place = world.restore_state(dynamic);
  check(in_place.ok(), when, in_place.ok() ? "" : in_place.error().message.c_str());
  check(world.state_hash() == hash, when, "the Dynamic image restores to another state_hash");
  return copy;
}

std::uint64_t fnv1a(const std::uint8_t* bytes, std::size_t size) {
  std::uint64_t hash = 14695981039346656037ull;
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 1099511628211ull;
  return hash;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  World world = make_fuzz_world();
  const std::uint64_t hash_before = world.state_hash();
  const Status restored = world.restore_state(std::span<const std::uint8_t>(data, size));
  if (!restored) {
    check(restored.error().code == ErrorCode::CorruptState, "refusal is not CorruptState");
    check(!restored.error().message.empty(), "refusal without a message");
    check(world.state_hash() == hash_before, "a refused image changed the world");
    return 0;
  }

  const std::vector<BodyId> ids = live_bodies(world);
  check_bodies_finite(world, ids);
  World copy = check_round_trip(world, "after restore:");
  // Bodies are neither created nor destroyed by a step, so `ids` stays valid.
  for (int i = 0; i < kSteps; ++i) {
    check(world.step(kDt).ok(), "step failed");
    check_bodies_finite(world, ids);
    check(copy.step(kDt).ok(), "step of the copy failed");
  }
  check(copy.state_hash() == world.state_hash(),
        "a world restored in place and one restored from the All image diverged");
  check_round_trip(world, "after 120 steps:");
  return 0;
}

// The configuration's fingerprint is FNV-1a of its bytes, which random mutation never matches:
// re-sign most mutated images that carry a configuration, so the fuzzer gets past the check into
// the configuration reader. The rest keep their fingerprint and test the check itself. Inputs
// stay plain images, so a reproducer is a file restore_state refuses or accepts by itself.
extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  size = LLVMFuzzerMutate(data, size, max_size);
  if (seed % 8 == 0 || size < kHeaderBytes || data[kHasConfigAt] != 1) return size;
  const auto config_bytes = load<std::uint32_t>(data + kConfigBytesAt);
  if (config_bytes > size - kHeaderBytes) return size;
  const std::uint64_t print = fnv1a(data + kHeaderBytes, config_bytes);
  std::memcpy(data + kFingerprintAt, &print, sizeof print);
  return size;
}
