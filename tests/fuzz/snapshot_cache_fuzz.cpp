// libFuzzer target, differential: the snapshot encoder with its cache (SnapshotEncodeCache, the
// layers chosen by the input) against the plain per-client encoder. Clients of one match are
// encoded twice a tick, once each way; the serialised snapshots and the reports must be equal
// byte for byte, or the target aborts. The input decides everything (snapshot_cache_input.h):
// the world's edits, every client's acknowledgements, budget and viewer, the cache's layers and
// stream slots, and encodes that go without the cache now and then.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "snapshot_cache_input.h"

namespace {

using namespace ricochet;

[[noreturn]] void mismatch(std::uint32_t tick, std::size_t client, const char* what) {
  std::fprintf(stderr, "snapshot_cache_fuzz: tick %u client %zu: cached and plain %s differ\n",
               tick, client, what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::CacheInput input(data, size);
  const proto::QuantizationSpec spec = fuzz::snapshot_spec();
  const fuzz::CacheSetup setup = input.setup();
  proto::SnapshotEncodeCache cache(setup.layers, setup.max_streams);
  std::vector<proto::SnapshotEncoder> plain, cached;
  for (std::size_t c = 0; c < setup.clients; ++c) {
    plain.emplace_back(spec);
    cached.emplace_back(spec);
  }
  std::vector<proto::QuantizedEntity> world = fuzz::snapshot_world(1);
  wire::Snapshot plain_out, cached_out;
  std::string plain_bytes, cached_bytes;
  for (std::uint32_t tick = 1; tick <= fuzz::kMaxCacheTicks && !input.empty(); ++tick) {
    input.edit_world(world, spec);
    for (std::size_t c = 0; c < setup.clients; ++c) {
      const fuzz::ClientTick client = input.client_tick(tick);
      if (client.ack) {
        plain[c].acknowledge(client.ack_tick);
        cached[c].acknowledge(client.ack_tick);
      }
      plain[c].encode(tick, world, client.viewer_m, client.budget_bytes, plain_out);
      if (client.without_cache) {
        cached[c].encode(tick, world, client.viewer_m, client.budget_bytes, cached_out);
      } else {
        cached[c].encode(tick, world, client.viewer_m, client.budget_bytes, cached_out, cache);
      }
      plain_out.SerializeToString(&plain_bytes);
      cached_out.SerializeToString(&cached_bytes);
      if (plain_bytes != cached_bytes) mismatch(tick, c, "snapshots");
      const proto::SnapshotEncodeReport& a = plain[c].last_report();
      const proto::SnapshotEncodeReport& b = cached[c].last_report();
      if (a.has_baseline != b.has_baseline || a.baseline_tick != b.baseline_tick ||
          a.entities != b.entities || a.pending != b.pending || a.sent != b.sent ||
          a.deferred != b.deferred || a.bytes != b.bytes) {
        mismatch(tick, c, "reports");
      }
      if (plain[c].ignored_acks() != cached[c].ignored_acks()) mismatch(tick, c, "ignored acks");
    }
  }
  return 0;
}
