#pragma once
/// A match's snapshots (match.h): when they are due, each connected player's ServerPayload built
/// from the tick's entity states, and the send phase that puts them, after the tick's events, in
/// the outbox.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mailbox.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/match.h"
#include "ricochet/wire/game.pb.h"
#include "roster.h"

namespace ricochet::server {

struct AddressedPayload {
  std::uint64_t account = 0;
  wire::ServerPayload payload;
};

struct Snapshots {
  explicit Snapshots(const proto::SnapshotCacheLayers& layers) : cache(layers) {}

  int interval_ticks = 1;  ///< steps between snapshots (tick rate / snapshot rate)
  int ticks_since = 0;     ///< steps since the last one
  std::vector<proto::QuantizedEntity> quantized;  ///< this snapshot's world
  proto::SnapshotEncodeCache cache;               ///< shared by the clients' encoders per tick
  std::vector<AddressedPayload> payloads;         ///< built this tick, one per connected player
  std::size_t payload_count = 0;                  ///< of payloads (kept for reuse), this tick's
};

/// Builds every connected player's payload for tick `tick` from `states` (sorted by id): its
/// snapshot within `budget_bytes`, its last input, its status. Hands each encoder the client's
/// newest acknowledgement.
void build_snapshots(std::uint32_t tick, std::span<const proto::EntityState> states,
                     const proto::QuantizationSpec& spec, std::size_t budget_bytes, Roster& roster,
                     Snapshots& snapshots);

/// Moves the pending events, then the payloads built this tick, serialised, to the outbox.
void send(Snapshots& snapshots, Mailbox& mailbox, MatchCounters& counters);

}  // namespace ricochet::server
