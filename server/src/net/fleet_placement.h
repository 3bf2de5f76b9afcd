#pragma once
/// What the control sessions need to place players across a fleet (PROTOCOL.md, Placement):
/// this server's id in the directory, the find_match limit per account, the ticket codec, and
/// the counters /metrics shows. The server owns one when [placement] is on; the control
/// sessions use it on the control server's strand (the counters are read from any thread).

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>

#include "claims_in_flight.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/token_bucket.h"

namespace ricochet::server {

/// How a find_match ended: ricochet_placement_tickets_total{result}.
enum class TicketResult : std::uint8_t {
  Assigned,
  NoServerAvailable,
  UnknownModeOrMap,
  RateLimited,     ///< over find_match_per_minute for the account
  InvalidRequest,  ///< a mode or map name the directory refuses
  ServerBusy,      ///< the database away or its queue full
  Failed,          ///< any other database error
};
inline constexpr std::size_t kTicketResultCount =
    static_cast<std::size_t>(TicketResult::Failed) + 1;
const char* name(TicketResult result);

/// How a directory heartbeat ended: ricochet_placement_heartbeats_total{outcome}.
enum class HeartbeatOutcome : std::uint8_t { Written, Failed };
inline constexpr std::size_t kHeartbeatOutcomeCount =
    static_cast<std::size_t>(HeartbeatOutcome::Failed) + 1;
const char* name(HeartbeatOutcome outcome);

struct PlacementCounters {
  std::array<std::atomic<std::uint64_t>, kTicketResultCount> tickets{};
  std::array<std::atomic<std::uint64_t>, kHeartbeatOutcomeCount> heartbeats{};

  void count(TicketResult result) {
    tickets[static_cast<std::size_t>(result)].fetch_add(1, std::memory_order_relaxed);
  }
  void count(HeartbeatOutcome outcome) {
    heartbeats[static_cast<std::size_t>(outcome)].fetch_add(1, std::memory_order_relaxed);
  }
};

/// find_match requests per account, across its connections: a token bucket each, forgotten
/// once refilled (so the map holds only accounts that asked lately).
class FindMatchLimiter {
 public:
  static constexpr double kBurst = 5;

  explicit FindMatchLimiter(double per_minute) : per_second_(per_minute / 60.0) {}
  /// False when the account is over its rate (nothing taken then).
  bool take(std::uint64_t account, proto::TimeUs now);
  std::size_t tracked() const { return buckets_.size(); }

 private:
  /// Drops the buckets back at their burst, when the map has grown past kPruneAt.
  void prune(proto::TimeUs now);
  static constexpr std::size_t kPruneAt = 4096;

  double per_second_;
  std::unordered_map<std::uint64_t, proto::TokenBucket> buckets_;
};

/// A ticket is 32 bytes on the wire and 64 lowercase hex digits in the database.
inline constexpr std::size_t kTicketBytes = 32;
std::string ticket_bytes(std::string_view hex);
/// Nothing when `bytes` is not kTicketBytes long.
std::optional<std::string> ticket_hex(std::string_view bytes);

/// A fresh server id for the directory: "rs-" and 16 random hex digits.
std::string draw_server_id();

struct FleetPlacement {
  std::string server_id;
  FindMatchLimiter limiter;
  PlacementCounters& counters;
  /// Seats of the match a ticket for a new match opens here ([matches] max_players, as the
  /// matches opened at start have), 1..64.
  int new_match_max_players = 16;
  /// Called on the control strand each time a ticket seated its player here (Agones: POST
  /// /allocate on the first); empty: nothing to tell. Must not block.
  std::function<void()> players_placed;
  /// The ticket joins claimed and not yet seated (on the wall clock), for the heartbeat's
  /// counted_ms.
  ClaimsInFlight claims{[] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  }};
};

}  // namespace ricochet::server
