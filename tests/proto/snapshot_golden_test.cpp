/// The encoder's output pinned bit for bit: a scripted scene (entities moving, joining and
/// leaving, acknowledgements arriving late, budgets from roomy to tight) hashed over every
/// serialised snapshot and report. The stored hash was taken before the encoder was optimised;
/// a change that alters it changes the wire output, which no speed-up may do.
///
/// The scene is built from std::mt19937's raw integers only (no distributions, no floats), so
/// the hash is the same on every standard library.

#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_test_world.h"

namespace ricochet::proto {
namespace {

class Fnv1a {
 public:
  void add(std::uint64_t value) {
    for (int k = 0; k < 8; ++k) add_byte(static_cast<std::uint8_t>(value >> (8 * k)));
  }
  void add(const std::string& bytes) {
    for (const char c : bytes) add_byte(static_cast<std::uint8_t>(c));
  }
  std::uint64_t value() const { return hash_; }

 private:
  void add_byte(std::uint8_t byte) {
    hash_ ^= byte;
    hash_ *= 1099511628211ull;
  }
  std::uint64_t hash_ = 14695981039346656037ull;
};

QuantizedEntity scripted_entity(std::uint32_t id, const QuantizationSpec& spec,
                                std::mt19937& random) {
  QuantizedEntity e;
  e.id = id;
  for (int a = 0; a < 3; ++a) {
    e.position[a] = random() % spec.position_steps(a);
    e.velocity[a] = static_cast<std::int32_t>(random() % 2001) - 1000;
  }
  if (random() % 2 == 0) {
    e.orientation_largest = static_cast<std::uint8_t>(random() % 4);
    for (std::int32_t& c : e.orientation) {
      c = static_cast<std::int32_t>(random() % 401) - 200;
    }
  }
  e.flags = random() % 4 == 0 ? static_cast<std::uint8_t>(random()) : 0;
  return e;
}

/// Moves about a third of the entities, sometimes exactly as predicted.
void step_world(std::vector<QuantizedEntity>& world, const QuantizationSpec& spec,
                std::mt19937& random) {
  for (QuantizedEntity& e : world) {
    if (random() % 3 != 0) continue;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t moved =
          static_cast<std::int64_t>(e.position[a]) + static_cast<std::int64_t>(random() % 81) - 40;
      e.position[a] = static_cast<std::uint32_t>(
          std::clamp<std::int64_t>(moved, 0, spec.position_steps(a) - 1));
      if (random() % 4 == 0) e.velocity[a] += static_cast<std::int32_t>(random() % 21) - 10;
    }
    if (random() % 5 == 0 && e.orientation_largest != 3) {
      e.orientation[random() % 3] = static_cast<std::int32_t>(random() % 401) - 200;
    }
    if (random() % 40 == 0) e.flags ^= 2;
  }
}

struct SceneResult {
  std::uint64_t hash = 0;
  int deferred_snapshots = 0;  ///< the budget left something out
  int delta_snapshots = 0;     ///< encoded against a baseline
};

SceneResult run_scene() {
  const QuantizationSpec spec = test::test_spec();
  std::mt19937 random(2024);
  std::vector<QuantizedEntity> world;
  std::uint32_t next_id = 1;
  for (int k = 0; k < 150; ++k) {
    next_id += 1 + random() % 3;
    world.push_back(scripted_entity(next_id, spec, random));
  }
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  std::deque<std::pair<std::uint32_t, std::uint32_t>> acks;  // (arrives at tick, acked tick)
  const std::size_t budgets[] = {1100, 1100, 400, 160, 60};
  Fnv1a hash;
  SceneResult scene;
  wire::Snapshot snapshot, received;
  for (std::uint32_t tick = 1; tick <= 240; ++tick) {
    step_world(world, spec, random);
    if (random() % 6 == 0 && !world.empty()) world.erase(world.begin() + random() % world.size());
    if (random() % 6 == 0) {
      next_id += 1 + random() % 3;
      world.push_back(scripted_entity(next_id, spec, random));
    }
    while (!acks.empty() && acks.front().first <= tick) {
      encoder.acknowledge(acks.front().second);
      acks.pop_front();
    }
    const std::array<float, 3> viewer{static_cast<float>(tick % 60) - 30, 1,
                                      static_cast<float>(tick % 17) * 2 - 16};
    encoder.encode(tick, world, viewer, budgets[(tick / 24) % 5], snapshot);
    const std::string bytes = snapshot.SerializeAsString();
    hash.add(bytes);
    const SnapshotEncodeReport& report = encoder.last_report();
    scene.deferred_snapshots += report.deferred > 0;
    scene.delta_snapshots += report.has_baseline;
    for (const std::uint64_t field :
         {std::uint64_t{report.has_baseline}, std::uint64_t{report.baseline_tick},
          std::uint64_t{report.entities}, std::uint64_t{report.pending}, std::uint64_t{report.sent},
          std::uint64_t{report.deferred}, std::uint64_t{report.bytes}}) {
      hash.add(field);
    }
    EXPECT_TRUE(received.ParseFromString(bytes));
    const SnapshotDecodeResult result = decoder.decode(received);
    EXPECT_TRUE(result.ok) << "tick " << tick << ": " << result.message;
    if (result.ok && tick % 7 != 0) acks.emplace_back(tick + 1 + tick % 9, decoder.newest_tick());
  }
  scene.hash = hash.value();
  return scene;
}

TEST(SnapshotGolden, EncoderOutputIsUnchangedBitForBit) {
  const SceneResult scene = run_scene();
  // The scene reaches the paths that matter: deltas, and budgets that defer entities.
  EXPECT_GT(scene.delta_snapshots, 100);
  EXPECT_GT(scene.deferred_snapshots, 20);
  EXPECT_EQ(scene.hash, 0x13e59c170cf8f0efull) << std::hex << "got 0x" << scene.hash;
}

}  // namespace
}  // namespace ricochet::proto
