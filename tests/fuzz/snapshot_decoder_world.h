#pragma once
/// The client state every snapshot_decoder input is decoded against, shared with its seed
/// writer: a decoder that already holds ticks 1..3 of a 40-entity world, and the encoder that
/// sent them (acknowledged up to tick 3) for the seeds to continue from.
///
/// Input format: records of a 2-byte big-endian length and that many bytes of a serialised
/// ricochet.wire.Snapshot, decoded in order (so a record may delta against an earlier one).

#include <cstdint>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"

namespace ricochet::fuzz {

inline proto::QuantizationSpec snapshot_spec() {
  proto::QuantizationSpec spec;
  spec.bounds = {{-20.0f, -1.0f, -20.0f}, {20.0f, 10.0f, 20.0f}};
  return spec;
}

/// Deterministic pseudo-random numbers.
struct SnapshotLcg {
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  std::uint32_t next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::uint32_t>(state >> 33);
  }
};

/// The world at `tick`: 40 entities (ids 1, 3, 5, ...), some rotating, a few moving each tick.
inline std::vector<proto::QuantizedEntity> snapshot_world(std::uint32_t tick) {
  const proto::QuantizationSpec spec = snapshot_spec();
  SnapshotLcg random;
  std::vector<proto::QuantizedEntity> world;
  for (std::uint32_t i = 0; i < 40; ++i) {
    proto::EntityState state;
    state.id = 1 + 2 * i;
    const float moving = i % 4 == 0 ? static_cast<float>(tick) : 0.0f;
    state.position_m = {static_cast<float>(random.next() % 3000) / 100 - 15 + 0.05f * moving, 0.5f,
                        static_cast<float>(random.next() % 3000) / 100 - 15};
    state.velocity_mps = {i % 4 == 0 ? 3.0f : 0.0f, 0, 0};
    if (i % 3 == 0) state.orientation_xyzw = {0.6f, 0.0f, 0.0f, 0.8f};
    state.flags = static_cast<std::uint8_t>(i % 5 == 0 ? 1 : 0);
    world.push_back(proto::quantize(state, spec));
  }
  return world;
}

/// Encodes ticks 1..3 into `decoder` (and `encoder`, acknowledged up to 3).
inline void prime_snapshot_client(proto::SnapshotEncoder& encoder,
                                  proto::SnapshotDecoder& decoder) {
  for (std::uint32_t tick = 1; tick <= 3; ++tick) {
    wire::Snapshot snapshot;
    const std::vector<proto::QuantizedEntity> world = snapshot_world(tick);
    encoder.encode(tick, world, {0, 0, 0}, 1100, snapshot);
    (void)decoder.decode(snapshot);
    encoder.acknowledge(tick);
  }
}

}  // namespace ricochet::fuzz
