#pragma once
/// What a bot reads from one game connection, sans-IO: untrusted ServerPayloads and GameEvents
/// in (bytes, as the transport delivers them), checked before use; the decoded view of the
/// match, the bot's own status and entity, and the ClientPayload to send out. A refusal is
/// counted and logged at debug level; nothing the server sends makes it assert. One GameFeed
/// per game connection (a reconnect starts a new one: input sequences restart at 1).

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "ricochet/bot/bot_metrics.h"
#include "ricochet/bot/input_history.h"
#include "ricochet/bot/world_view.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::bot {

struct FeedCounts {
  std::uint64_t snapshots = 0;          ///< decoded
  std::uint64_t snapshots_refused = 0;  ///< refused by the decoder (any reason)
  /// Not a ServerPayload, a snapshot tick that is not the server_tick, or an acknowledgement of
  /// an input this connection never sent.
  std::uint64_t bad_payloads = 0;
  std::uint64_t bad_events = 0;  ///< not a GameEvent, or one with no event set
};

class GameFeed {
 public:
  /// spec: the join reply's, validated (proto::from_wire). ticks_per_snapshot: tick rate over
  /// snapshot rate, >= 1. log_name: who this is in the log.
  GameFeed(const proto::QuantizationSpec& spec, double ticks_per_snapshot, std::string log_name);

  /// One unreliable message. True when it carried a snapshot that decoded.
  bool read_payload(std::span<const std::uint8_t> bytes);
  /// One reliable message: the event when it is one (already applied to the view).
  std::optional<wire::GameEvent> read_event(std::span<const std::uint8_t> bytes);
  /// The ClientPayload to send this tick: `input` numbered next, with the newest few before it
  /// and the newest snapshot tick decoded as the acknowledgement. An input without a view_tick
  /// claims the newest snapshot's tick. Valid until the next call: the message and its bytes
  /// are kept from tick to tick, so writing one allocates nothing.
  const std::string& write_payload(wire::Input input);

  const WorldView& view() const { return view_; }
  const wire::PlayerStatus& status() const { return status_; }
  /// The entity the server says is ours (newest payload); 0 before the first payload.
  std::uint32_t own_entity_id() const { return own_entity_id_; }
  const InputHistory& inputs() const { return inputs_; }
  const SnapshotGapCounter& gaps() const { return gaps_; }
  const FeedCounts& counts() const { return counts_; }

 private:
  proto::SnapshotDecoder decoder_;
  WorldView view_;
  SnapshotGapCounter gaps_;
  InputHistory inputs_;
  wire::ServerPayload
      incoming_;                 ///< read_payload parses into it, reused (its parts stay allocated)
  wire::ClientPayload payload_;  ///< write_payload's, reused
  std::string payload_bytes_;
  wire::PlayerStatus status_;
  std::uint32_t own_entity_id_ = 0;
  FeedCounts counts_;
  std::string log_name_;
};

}  // namespace ricochet::bot
