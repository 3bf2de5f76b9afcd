/// tests/vectors/snapshots_spheres901.txt and snapshots_players64.txt: a few hundred ticks of one
/// client's snapshot stream of a snapshot-bench scene (tools/bench/snapshot_scenes.h), as the C++
/// encoder writes it and the C++ decoder reads it, with some snapshots lost on the way so that
/// deltas against older baselines (and, in spheres901, a stream restarted without a baseline)
/// appear. The scene runs a while before the client joins, so the stream starts with everything
/// moving and the budget (1100 bytes) deferring part of the first snapshots.
///   spec scene=NAME entities=N bytes=HEX
///     HEX: the wire::Quantization both ends use (what JoinMatchReply.quantization carries).
///   refusal tick=T corruption=NAME reason=NAME bytes=HEX
///     HEX: a wire::Snapshot, a corruption of the next snapshot record's, which the decoder in
///     its current state refuses with `reason` (snapshot_codec.h's name()); the decoder is then
///     as it was. NAME: truncated, bit_flip, extra_byte, stale, baseline_after_tick,
///     unknown_baseline, oversized.
///   snapshot tick=T baseline_age=A bytes=HEX ack=T
///     HEX: a serialised wire::Snapshot the client received; the decoder accepts it and then
///     acknowledges `ack` (its newest tick). Lost snapshots have no record.
///   state tick=T count=N hash=HEX
///     After the snapshot of tick T: the client holds N entities; HEX is the 8-byte FNV-1a 64
///     (big-endian) of their canonical bytes in id order (below).
///   entities tick=T bytes=HEX
///     Every 50th snapshot and the last: the canonical bytes of every entity the client holds,
///     42 per entity, little-endian: id u32, position[3] u32, velocity[3] i32,
///     orientation_largest u8, orientation[3] i32, flags u8. floats=HEX: the FNV-1a 64 of what
///     proto::dequantize shows for them, 40 bytes per entity: the IEEE bits (u32 little-endian)
///     of position_m[3], velocity_mps[3], orientation_xyzw[4].

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_scenes.h"
#include "vector_file.h"

namespace ricochet::vectors {
namespace {

constexpr std::size_t kBudgetBytes = 1100;
constexpr int kAckDelayTicks = 6;  ///< 100 ms at 60 Hz
constexpr int kRecordedTicks = 300;
constexpr int kFullStateEvery = 50;
constexpr int kRefusalsEvery = 25;

/// What the link does to the snapshot sent at the recorded tick `index`.
struct LossPlan {
  int burst_begin = 0, burst_end = 0;  ///< lost: [begin, end)
  int long_burst_begin = 0, long_burst_end = 0;

  bool lost(int index) const {
    if (index < 40) return false;  // the first snapshots arrive: the client fills up first
    if (index % 11 == 7) return true;
    if (index >= burst_begin && index < burst_end) return true;
    return index >= long_burst_begin && index < long_burst_end;
  }
};

void append_le(std::vector<std::uint8_t>& out, std::uint32_t value, int bytes) {
  for (int k = 0; k < bytes; ++k) out.push_back(static_cast<std::uint8_t>(value >> (8 * k)));
}

std::vector<std::uint8_t> canonical_bytes(std::span<const proto::QuantizedEntity> entities) {
  std::vector<std::uint8_t> out;
  out.reserve(entities.size() * 42);
  for (const proto::QuantizedEntity& e : entities) {
    append_le(out, e.id, 4);
    for (const std::uint32_t p : e.position) append_le(out, p, 4);
    for (const std::int32_t v : e.velocity) append_le(out, static_cast<std::uint32_t>(v), 4);
    append_le(out, e.orientation_largest, 1);
    for (const std::int32_t c : e.orientation) append_le(out, static_cast<std::uint32_t>(c), 4);
    append_le(out, e.flags, 1);
  }
  return out;
}

std::vector<std::uint8_t> dequantized_bytes(std::span<const proto::QuantizedEntity> entities,
                                            const proto::QuantizationSpec& spec) {
  std::vector<std::uint8_t> out;
  out.reserve(entities.size() * 40);
  for (const proto::QuantizedEntity& e : entities) {
    const proto::EntityState state = proto::dequantize(e, spec);
    for (const float f : state.position_m) append_le(out, std::bit_cast<std::uint32_t>(f), 4);
    for (const float f : state.velocity_mps) append_le(out, std::bit_cast<std::uint32_t>(f), 4);
    for (const float f : state.orientation_xyzw) {
      append_le(out, std::bit_cast<std::uint32_t>(f), 4);
    }
  }
  return out;
}

std::array<std::uint8_t, 8> fnv1a64(const std::vector<std::uint8_t>& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325u;
  for (const std::uint8_t b : bytes) {
    hash ^= b;
    hash *= 0x100000001b3u;
  }
  std::array<std::uint8_t, 8> out{};
  for (int k = 0; k < 8; ++k) out[k] = static_cast<std::uint8_t>(hash >> (56 - 8 * k));
  return out;
}

/// Writes the corruptions of `snapshot` that `decoder` refuses, each tried on a copy.
void add_refusals(VectorFile& file, const proto::SnapshotDecoder& decoder,
                  const wire::Snapshot& snapshot, std::uint64_t& seed) {
  auto attempt = [&](const char* corruption, const wire::Snapshot& corrupted) {
    proto::SnapshotDecoder copy = decoder;
    const proto::SnapshotDecodeResult result = copy.decode(corrupted);
    if (result.ok) return;
    file.add(Record("refusal")
                 .number("tick", snapshot.tick())
                 .word("corruption", corruption)
                 .word("reason", proto::name(result.reason))
                 .bytes("bytes", corrupted.SerializeAsString()));
  };
  const std::string& stream = snapshot.entities();
  wire::Snapshot corrupted = snapshot;
  if (!stream.empty()) {
    corrupted.set_entities(stream.substr(0, stream.size() - 1));
    attempt("truncated", corrupted);
  }
  for (int flip = 0; flip < 4 && !stream.empty(); ++flip) {
    seed = seed * 6364136223846793005u + 1442695040888963407u;
    const std::size_t bit = (seed >> 33) % (stream.size() * 8);
    std::string flipped = stream;
    flipped[bit / 8] = static_cast<char>(flipped[bit / 8] ^ (0x80 >> (bit % 8)));
    corrupted.set_entities(flipped);
    attempt("bit_flip", corrupted);
  }
  corrupted.set_entities(stream + '\x80');
  attempt("extra_byte", corrupted);
  corrupted.set_entities(std::string(proto::kMaxSnapshotStreamBytes + 1, '\0'));
  attempt("oversized", corrupted);
  corrupted.set_entities(stream);
  if (decoder.has_snapshot()) {
    corrupted.set_tick(decoder.newest_tick());
    attempt("stale", corrupted);
    corrupted.set_tick(snapshot.tick());
  }
  corrupted.set_baseline_age(snapshot.tick() + 1);
  attempt("baseline_after_tick", corrupted);
  corrupted.set_baseline_age(std::min<std::uint32_t>(snapshot.tick(), 65));
  attempt("unknown_baseline", corrupted);
}

std::string write_stream(bench::SnapshotScene scene, int preroll_steps, const LossPlan& loss) {
  if (const std::string problem = scene.spec.validate(); !problem.empty()) {
    throw std::logic_error("snapshot scene spec: " + problem);
  }
  VectorFile file("snapshots_" + scene.name,
                  "One client's snapshot stream of snapshot-bench's " + scene.name +
                      " scene, lost snapshots and corruptions\n"
                      "the decoder refuses included (tools/vectors/snapshots_vectors.cpp).");
  wire::Quantization quantization;
  proto::to_wire(scene.spec, quantization);
  file.add(Record("spec")
               .word("scene", scene.name)
               .number("entities", static_cast<std::int64_t>(scene.bodies.size()))
               .bytes("bytes", quantization.SerializeAsString()));

  proto::SnapshotEncoder encoder(scene.spec);
  proto::SnapshotDecoder decoder(scene.spec);
  std::vector<std::pair<int, std::uint32_t>> acks;  ///< (arrives at step, acked tick)
  std::vector<proto::QuantizedEntity> world;
  wire::Snapshot sent, received;
  std::uint64_t seed = 30;
  int delivered = 0;
  const physics::Real dt = physics::Real(1) / 60;
  for (int step = 0; step < preroll_steps + kRecordedTicks; ++step) {
    scene.drive(scene, step, true);
    if (!scene.world.step(dt).ok()) throw std::logic_error("snapshot scene step failed");
    const auto tick = static_cast<std::uint32_t>(step + 1);
    if (step < preroll_steps) continue;
    const int index = step - preroll_steps;
    while (!acks.empty() && acks.front().first <= step) {
      encoder.acknowledge(acks.front().second);
      acks.erase(acks.begin());
    }
    bench::read_entities(scene, world);
    encoder.encode(tick, world, scene.viewer(scene, 0), kBudgetBytes, sent);
    if (loss.lost(index)) continue;
    if (!received.ParseFromString(sent.SerializeAsString())) {
      throw std::logic_error("snapshot does not parse");
    }
    if (delivered % kRefusalsEvery == 3) add_refusals(file, decoder, received, seed);
    const proto::SnapshotDecodeResult result = decoder.decode(received);
    if (!result.ok) throw std::logic_error("snapshot refused: " + result.message);
    acks.emplace_back(step + kAckDelayTicks, decoder.newest_tick());
    file.add(Record("snapshot")
                 .number("tick", received.tick())
                 .number("baseline_age", received.baseline_age())
                 .bytes("bytes", received.SerializeAsString())
                 .number("ack", decoder.newest_tick()));
    const std::vector<std::uint8_t> state = canonical_bytes(result.entities);
    file.add(Record("state")
                 .number("tick", received.tick())
                 .number("count", static_cast<std::int64_t>(result.entities.size()))
                 .bytes("hash", fnv1a64(state)));
    const bool last = index == kRecordedTicks - 1;
    if (delivered % kFullStateEvery == 0 || last) {
      file.add(Record("entities")
                   .number("tick", received.tick())
                   .bytes("bytes", state)
                   .bytes("floats", fnv1a64(dequantized_bytes(result.entities, scene.spec))));
    }
    ++delivered;
  }
  return file.text();
}

}  // namespace

std::string write_snapshots_spheres901_vectors() {
  // 5 s in, the ball reaches the grid; a 70-tick loss outlives the 64-snapshot rings, so the
  // stream starts again without a baseline.
  return write_stream(bench::spheres_scene("spheres901", bench::kSpheresSpacing), 300,
                      LossPlan{100, 112, 180, 250});
}

std::string write_snapshots_players64_vectors() {
  return write_stream(bench::players_scene(64), 60, LossPlan{100, 112, 0, 0});
}

}  // namespace ricochet::vectors
