// libFuzzer target: the snapshot decoder (proto/snapshot_codec.h) on untrusted snapshots. Every
// input is a sequence of records (snapshot_decoder_world.h) decoded by a client that holds ticks
// 1..3 of a known world. Nothing may crash, and what the decoder accepts must be a valid entity
// set: ids strictly increasing, every field within the spec's ranges.

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "snapshot_decoder_world.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ricochet;
  const proto::QuantizationSpec spec = fuzz::snapshot_spec();
  proto::SnapshotEncoder encoder(spec);
  proto::SnapshotDecoder decoder(spec);
  fuzz::prime_snapshot_client(encoder, decoder);

  std::size_t at = 0;
  while (at + 2 <= size) {
    const std::size_t length = (static_cast<std::size_t>(data[at]) << 8) | data[at + 1];
    at += 2;
    if (length > size - at) break;
    wire::Snapshot snapshot;
    const bool parsed = snapshot.ParseFromArray(data + at, static_cast<int>(length));
    at += length;
    if (!parsed) continue;
    const proto::SnapshotDecodeResult result = decoder.decode(snapshot);
    if (!result.ok) continue;
    for (std::size_t k = 0; k < result.entities.size(); ++k) {
      if (!proto::in_range(result.entities[k], spec)) std::abort();
      if (k > 0 && !(result.entities[k - 1].id < result.entities[k].id)) std::abort();
    }
    if (decoder.newest_tick() != snapshot.tick()) std::abort();
  }
  return 0;
}
