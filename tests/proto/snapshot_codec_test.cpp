/// The encoder and decoder together: round trips, deltas, acknowledgements, joins and leaves,
/// the byte budget and the priority order.

#include "ricochet/proto/snapshot_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "snapshot_test_world.h"

namespace ricochet::proto::snapshot_codec_test {
namespace {

using test::random_world;
using test::test_spec;

constexpr std::size_t kBudget = 1100;
constexpr std::array<float, 3> kOrigin{0, 0, 0};

std::vector<QuantizedEntity> decoded(const SnapshotDecodeResult& result) {
  return {result.entities.begin(), result.entities.end()};
}

TEST(SnapshotCodec, AFullSnapshotRoundTripsBitForBit) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(11);
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<QuantizedEntity> world = random_world(random() % 60, spec, random);
    SnapshotEncoder encoder(spec);
    SnapshotDecoder decoder(spec);
    wire::Snapshot snapshot;
    encoder.encode(100, world, kOrigin, kBudget, snapshot);
    EXPECT_EQ(snapshot.baseline_age(), 0u);
    EXPECT_LE(snapshot.ByteSizeLong(), kBudget);
    EXPECT_EQ(encoder.last_report().deferred, 0u);
    // Through the wire format, as a client receives it.
    wire::Snapshot received;
    ASSERT_TRUE(received.ParseFromString(snapshot.SerializeAsString()));
    const SnapshotDecodeResult result = decoder.decode(received);
    ASSERT_TRUE(result.ok) << result.message;
    EXPECT_EQ(decoded(result), world);
    EXPECT_EQ(decoder.newest_tick(), 100u);
  }
}

/// The widest fields a valid spec allows (2^31 position steps per axis, velocities of nearly
/// 2^30 steps, 16-bit orientation components): new entities still round-trip.
TEST(SnapshotCodec, TheWidestSpecRoundTrips) {
  QuantizationSpec spec;
  spec.bounds = {{-1000.0f, -1000.0f, -1000.0f}, {1000.0f, 1000.0f, 1000.0f}};
  spec.position_step_m = 0.000001f;  // 2e9 steps per axis
  spec.velocity_step_mps = 0.0000001f;
  spec.max_speed_mps = 100.0f;  // 1e9 steps
  spec.orientation_bits = 16;
  ASSERT_EQ(spec.validate(), "");
  std::mt19937 random(5);
  const std::vector<QuantizedEntity> world = random_world(20, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  encoder.encode(1, world, kOrigin, kBudget, snapshot);
  EXPECT_EQ(encoder.last_report().deferred, 0u);
  const SnapshotDecodeResult result = decoder.decode(snapshot);
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(decoded(result), world);
}

/// A client over a lossy link: snapshots and acks are lost, acks arrive late, entities move,
/// join and leave. Whenever the encoder sent everything, the client holds the world exactly.
TEST(SnapshotCodec, DeltasOverALossyLinkDecodeToTheServerState) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(12);
  std::vector<QuantizedEntity> world = random_world(80, spec, random);
  std::uint32_t next_id = world.back().id + 1;
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> acks_in_flight;  // arrive at, tick
  int complete = 0, deltas = 0;
  for (std::uint32_t tick = 1; tick <= 600; ++tick) {
    test::perturb(world, spec, random);
    if (random() % 10 == 0 && !world.empty()) world.erase(world.begin() + random() % world.size());
    if (random() % 10 == 0) world.push_back(test::random_entity(next_id++, spec, random, true));
    for (const auto& [arrive, acked] : acks_in_flight) {
      if (arrive == tick) encoder.acknowledge(acked);
    }
    wire::Snapshot snapshot;
    encoder.encode(tick, world, kOrigin, kBudget, snapshot);
    ASSERT_LE(snapshot.ByteSizeLong(), kBudget);
    if (random() % 5 == 0) continue;  // lost on the way
    const SnapshotDecodeResult result = decoder.decode(snapshot);
    ASSERT_TRUE(result.ok) << "tick " << tick << ": " << result.message;
    deltas += snapshot.baseline_age() != 0;
    if (encoder.last_report().deferred == 0) {
      ++complete;
      ASSERT_EQ(decoded(result), world) << "tick " << tick;
    }
    if (random() % 5 != 0) acks_in_flight.emplace_back(tick + 3 + random() % 6, tick);
  }
  EXPECT_GT(complete, 400);
  EXPECT_GT(deltas, 400);
}

TEST(SnapshotCodec, AnUnchangedWorldCostsAFewBitsInTotal) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(13);
  const std::vector<QuantizedEntity> world = random_world(900, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  // The full world takes several budget-limited snapshots to reach the client.
  std::uint32_t tick = 1;
  for (; tick < 100; ++tick) {
    encoder.encode(tick, world, kOrigin, kBudget, snapshot);
    ASSERT_TRUE(decoder.decode(snapshot).ok);
    encoder.acknowledge(decoder.newest_tick());
    if (encoder.last_report().pending == 0) break;
  }
  ASSERT_LT(tick, 100u);
  encoder.encode(++tick, world, kOrigin, kBudget, snapshot);
  EXPECT_EQ(snapshot.entities().size(), 1u);  // three zero counts and padding
  EXPECT_LE(snapshot.ByteSizeLong(), 8u);
  const SnapshotDecodeResult result = decoder.decode(snapshot);
  ASSERT_TRUE(result.ok);
  EXPECT_EQ(decoded(result), world);
}

TEST(SnapshotCodec, TheBudgetHoldsAndTheNearestGoFirst) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(14);
  std::vector<QuantizedEntity> world = random_world(600, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  const std::array<float, 3> viewer{20.0f, 0.0f, 20.0f};
  const std::size_t budget = 300;
  wire::Snapshot snapshot;
  encoder.encode(1, world, viewer, budget, snapshot);
  EXPECT_LE(snapshot.ByteSizeLong(), budget);
  EXPECT_GT(encoder.last_report().deferred, 0u);
  const SnapshotDecodeResult result = decoder.decode(snapshot);
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_FALSE(result.entities.empty());
  // Everything sent is nearer than the median of what was not.
  auto distance = [&](const QuantizedEntity& e) {
    const EntityState s = dequantize(e, spec);
    double d = 0;
    for (int a = 0; a < 3; ++a) d += (s.position_m[a] - viewer[a]) * (s.position_m[a] - viewer[a]);
    return std::sqrt(d);
  };
  double farthest_sent = 0;
  for (const QuantizedEntity& e : result.entities)
    farthest_sent = std::max(farthest_sent, distance(e));
  std::vector<double> unsent;
  for (const QuantizedEntity& e : world) {
    if (!std::binary_search(result.entities.begin(), result.entities.end(), e,
                            [](const auto& a, const auto& b) { return a.id < b.id; })) {
      unsent.push_back(distance(e));
    }
  }
  std::sort(unsent.begin(), unsent.end());
  EXPECT_LT(farthest_sent, unsent[unsent.size() / 2]);
}

TEST(SnapshotCodec, AtTheSameDistanceTheMostChangedGoFirst) {
  const QuantizationSpec spec = test_spec();
  // 200 entities on a ring around the viewer, all at rest and known to the client.
  std::vector<QuantizedEntity> world(200);
  for (std::uint32_t i = 0; i < world.size(); ++i) {
    EntityState state;
    state.id = i + 1;
    const float angle = 6.2831853f * static_cast<float>(i) / static_cast<float>(world.size());
    state.position_m = {10 * std::cos(angle), 1, 10 * std::sin(angle)};
    world[i] = quantize(state, spec);
  }
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  std::uint32_t tick = 1;
  for (; encoder.last_report().pending > 0 || tick == 1; ++tick) {
    encoder.encode(tick, world, kOrigin, kBudget, snapshot);
    ASSERT_TRUE(decoder.decode(snapshot).ok);
    encoder.acknowledge(tick);
  }
  // Odd ids move 2 m, even ids 2 cm; the budget holds about a third of them.
  for (QuantizedEntity& e : world) e.position[1] += e.id % 2 == 1 ? 2000 : 20;
  encoder.encode(tick, world, kOrigin, 60, snapshot);
  ASSERT_GT(encoder.last_report().deferred, 0u);
  const SnapshotDecodeResult result = decoder.decode(snapshot);
  ASSERT_TRUE(result.ok);
  int far_moved = 0, near_moved = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (result.entities[i] != world[i]) continue;  // not sent yet
    (world[i].id % 2 == 1 ? far_moved : near_moved) += 1;
  }
  EXPECT_GT(far_moved, 0);
  EXPECT_EQ(near_moved, 0);
}

TEST(SnapshotCodec, StarvedEntitiesAreSentSoonerAndTheClientConverges) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(15);
  std::vector<QuantizedEntity> world = random_world(400, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  const std::size_t budget = 200;
  wire::Snapshot snapshot;
  std::uint32_t tick = 1;
  // Everything moves for a while under a tight budget...
  for (; tick <= 60; ++tick) {
    test::perturb(world, spec, random);
    encoder.encode(tick, world, kOrigin, budget, snapshot);
    ASSERT_LE(snapshot.ByteSizeLong(), budget);
    ASSERT_TRUE(decoder.decode(snapshot).ok);
    encoder.acknowledge(tick);
  }
  // ...then stops; the far entities catch up within a bounded number of snapshots.
  int catch_up = 0;
  SnapshotDecodeResult result;
  do {
    encoder.encode(tick, world, kOrigin, budget, snapshot);
    result = decoder.decode(snapshot);
    ASSERT_TRUE(result.ok);
    encoder.acknowledge(tick++);
    ++catch_up;
  } while (encoder.last_report().pending > 0 && catch_up < 200);
  EXPECT_LT(catch_up, 200);
  EXPECT_EQ(decoded(result), world);
}

/// Entities gliding at constant velocity move exactly as predicted: each costs its run length
/// and a repeated mask, about two bits, though every one of them changes every tick.
/// Small changes everywhere and a respawn now and then: the respawned entity's delta is long
/// (written field by field rather than copied), and it still decodes to the server state.
TEST(SnapshotCodec, ATeleportAmongSmallChangesDecodesToTheServerState) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(7);
  std::vector<QuantizedEntity> world = test::random_world(80, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  int complete = 0;
  for (std::uint32_t tick = 1; tick <= 200; ++tick) {
    test::perturb(world, spec, random);
    test::teleport(world, spec, random);
    if (tick > 3) encoder.acknowledge(tick - 3);
    encoder.encode(tick, world, kOrigin, kBudget, snapshot);
    const SnapshotDecodeResult result = decoder.decode(snapshot);
    ASSERT_TRUE(result.ok) << result.message;
    if (encoder.last_report().deferred == 0) {
      ASSERT_EQ(decoded(result), world) << "tick " << tick;
      ++complete;
    }
  }
  EXPECT_GT(complete, 150);
}

TEST(SnapshotCodec, ConstantVelocityIsPredictedAndNearlyFree) {
  const QuantizationSpec spec = test_spec();  // 1 mm, 0.01 m/s, 60 Hz
  std::vector<QuantizedEntity> world(200);
  for (std::uint32_t i = 0; i < world.size(); ++i) {
    world[i].id = i + 1;
    world[i].position = {1000 + 10 * i, 5000, 20000};
    world[i].velocity = {600, 0, -300};  // 6 and -3 m/s: 100 and -50 mm per tick
  }
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  for (std::uint32_t tick = 1; tick <= 120; ++tick) {
    for (QuantizedEntity& e : world) {
      e.position[0] += 100;
      e.position[2] -= 50;
    }
    if (tick > 8) encoder.acknowledge(tick - 6);  // 100 ms late
    encoder.encode(tick, world, kOrigin, kBudget, snapshot);
    const SnapshotDecodeResult result = decoder.decode(snapshot);
    ASSERT_TRUE(result.ok) << result.message;
    if (tick > 20) {
      ASSERT_EQ(snapshot.baseline_age(), 6u);
      ASSERT_EQ(encoder.last_report().sent, 200u);
      ASSERT_EQ(decoded(result), world);
      EXPECT_LE(snapshot.entities().size() * 8, 200u * 2 + 64) << "tick " << tick;
    }
  }
}

TEST(SnapshotCodec, EveryBudgetHolds) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(19);
  std::vector<QuantizedEntity> world = random_world(300, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  for (std::uint32_t tick = 1; tick <= 300; ++tick) {
    test::perturb(world, spec, random);
    const std::size_t budget = 16 + random() % 1085;
    encoder.encode(tick, world, kOrigin, budget, snapshot);
    ASSERT_LE(snapshot.ByteSizeLong(), budget) << "tick " << tick;
    ASSERT_EQ(encoder.last_report().bytes, snapshot.ByteSizeLong());
    ASSERT_TRUE(decoder.decode(snapshot).ok);
    if (random() % 2 == 0) encoder.acknowledge(tick);
  }
}

TEST(SnapshotCodec, AcknowledgementsOfUnknownOrOlderTicksAreIgnored) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(16);
  const std::vector<QuantizedEntity> world = random_world(10, spec, random);
  SnapshotEncoder encoder(spec);
  wire::Snapshot snapshot;
  encoder.acknowledge(5);  // nothing sent yet
  EXPECT_EQ(encoder.ignored_acks(), 1u);
  encoder.encode(1, world, kOrigin, kBudget, snapshot);
  encoder.encode(2, world, kOrigin, kBudget, snapshot);
  encoder.acknowledge(2);
  encoder.acknowledge(1);           // older than the baseline
  encoder.acknowledge(2 + 64);      // same ring slot, never sent
  encoder.acknowledge(0xFFFFFFFF);  // garbage
  EXPECT_EQ(encoder.ignored_acks(), 4u);
  encoder.encode(3, world, kOrigin, kBudget, snapshot);
  EXPECT_EQ(snapshot.baseline_age(), 1u);
  EXPECT_EQ(encoder.last_report().baseline_tick, 2u);
}

TEST(SnapshotCodec, ABaselineOlderThanTheRingGivesAFullSnapshot) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(17);
  const std::vector<QuantizedEntity> world = random_world(20, spec, random);
  SnapshotEncoderOptions options;
  options.ring_size = 8;
  SnapshotEncoder encoder(spec, options);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  encoder.encode(1, world, kOrigin, kBudget, snapshot);
  ASSERT_TRUE(decoder.decode(snapshot).ok);
  encoder.acknowledge(1);
  for (std::uint32_t tick = 2; tick <= 9; ++tick)
    encoder.encode(tick, world, kOrigin, kBudget, snapshot);
  EXPECT_EQ(snapshot.baseline_age(), 8u);  // tick 9 still deltas against 1, then overwrites it
  encoder.encode(10, world, kOrigin, kBudget, snapshot);
  EXPECT_EQ(snapshot.baseline_age(), 0u);
  const SnapshotDecodeResult result = decoder.decode(snapshot);
  ASSERT_TRUE(result.ok);
  EXPECT_EQ(decoded(result), world);
}

TEST(SnapshotCodec, EntitiesJoinAndLeave) {
  const QuantizationSpec spec = test_spec();
  std::mt19937 random(18);
  std::vector<QuantizedEntity> world = random_world(30, spec, random);
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  wire::Snapshot snapshot;
  encoder.encode(1, world, kOrigin, kBudget, snapshot);
  ASSERT_TRUE(decoder.decode(snapshot).ok);
  encoder.acknowledge(1);
  world.erase(world.begin() + 3, world.begin() + 9);
  world.erase(world.begin());
  const std::uint32_t last_id = world.back().id;
  world.push_back(test::random_entity(last_id + 50, spec, random, false));
  world.push_back(test::random_entity(last_id + 100, spec, random, true));
  const std::uint32_t between = world[4].id + 1;  // ids go up by 2..4, so this one is free
  if (between < world[5].id)
    world.insert(world.begin() + 5, test::random_entity(between, spec, random, true));
  encoder.encode(2, world, kOrigin, kBudget, snapshot);
  EXPECT_EQ(snapshot.baseline_age(), 1u);
  const SnapshotDecodeResult result = decoder.decode(snapshot);
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(decoded(result), world);
  // Everyone leaves.
  encoder.acknowledge(2);
  encoder.encode(3, {}, kOrigin, kBudget, snapshot);
  const SnapshotDecodeResult empty = decoder.decode(snapshot);
  ASSERT_TRUE(empty.ok);
  EXPECT_TRUE(empty.entities.empty());
}

}  // namespace
}  // namespace ricochet::proto::snapshot_codec_test
