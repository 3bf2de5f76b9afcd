// Writes the seed corpus of snapshot_decoder_fuzz: real encoder output continuing from the
// primed client (snapshot_decoder_world.h) — deltas with moves, joins, leaves, flag changes, a
// budget-limited snapshot, a full snapshot and chains of several. Run by
// `tools/fuzz.sh --seeds`; the output is committed in tests/fuzz/corpus/snapshot_decoder/.
//
//   snapshot_decoder_seeds DIR

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "snapshot_decoder_world.h"

namespace {

using namespace ricochet;

void append_record(std::string& out, const wire::Snapshot& snapshot) {
  const std::string bytes = snapshot.SerializeAsString();
  out.push_back(static_cast<char>(bytes.size() >> 8));
  out.push_back(static_cast<char>(bytes.size() & 0xFF));
  out += bytes;
}

void write_file(const std::string& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir + "/" + name + ".bin";
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() ||
      std::fclose(file) != 0) {
    std::fprintf(stderr, "snapshot_decoder_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  std::printf("%-24s %5zu bytes\n", name.c_str(), bytes.size());
}

/// Snapshots from tick 4 on, `count` of them, acknowledged `ack_every` ticks (0: never), of the
/// world changed by `edit`, within `budget` bytes, as one input.
template <class Edit>
std::string sequence(int count, int ack_every, std::size_t budget, Edit&& edit) {
  const proto::QuantizationSpec spec = fuzz::snapshot_spec();
  proto::SnapshotEncoder encoder(spec);
  proto::SnapshotDecoder decoder(spec);
  fuzz::prime_snapshot_client(encoder, decoder);
  std::string out;
  for (int k = 0; k < count; ++k) {
    const std::uint32_t tick = 4 + static_cast<std::uint32_t>(k);
    std::vector<proto::QuantizedEntity> world = fuzz::snapshot_world(tick);
    edit(world, k);
    wire::Snapshot snapshot;
    encoder.encode(tick, world, {0, 0, 0}, budget, snapshot);
    if (!decoder.decode(snapshot).ok) {
      std::fprintf(stderr, "snapshot_decoder_seeds: the decoder refused tick %u\n", tick);
      std::exit(1);
    }
    append_record(out, snapshot);
    if (ack_every > 0 && k % ack_every == 0) encoder.acknowledge(tick);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: snapshot_decoder_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  auto none = [](std::vector<proto::QuantizedEntity>&, int) {};
  write_file(dir, "delta_moves", sequence(1, 0, 1100, none));
  write_file(dir, "delta_chain", sequence(8, 2, 1100, none));
  write_file(dir, "joins_and_leaves",
             sequence(4, 1, 1100, [](std::vector<proto::QuantizedEntity>& world, int k) {
               world.erase(world.begin() + k, world.begin() + k + 3);
               proto::QuantizedEntity joined = world.back();
               joined.id += 10 + static_cast<std::uint32_t>(k);
               joined.orientation_largest = 1;
               joined.orientation = {100, -50, 3};
               world.push_back(joined);
             }));
  write_file(dir, "flags_and_turns",
             sequence(3, 1, 1100, [](std::vector<proto::QuantizedEntity>& world, int k) {
               for (std::size_t i = 0; i < world.size(); i += 3) {
                 world[i].flags ^= 0x80;
                 world[i].orientation[0] += k + 1;
                 world[i].orientation_largest = static_cast<std::uint8_t>((i / 3 + k) % 4);
               }
             }));
  write_file(dir, "budget_limited",
             sequence(3, 0, 40, [](std::vector<proto::QuantizedEntity>& world, int k) {
               for (proto::QuantizedEntity& e : world) e.position[1] += 500 + 7 * k;
             }));
  // A client that lost its baseline gets a full snapshot (age 0).
  {
    const proto::QuantizationSpec spec = fuzz::snapshot_spec();
    proto::SnapshotEncoder encoder(spec);
    wire::Snapshot snapshot;
    encoder.encode(9, fuzz::snapshot_world(9), {0, 0, 0}, 1100, snapshot);
    std::string out;
    append_record(out, snapshot);
    write_file(dir, "full", out);
  }
  return 0;
}
