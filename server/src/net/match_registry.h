#pragma once
/// The matches this process hosts and who sits where. It is the control channel's
/// MatchDirectory (list, create, join, leave, chat) and the game channel's GameRouter (a
/// connection came up, went away, sent bytes), and hands each to the right MatchHost.
///
/// Seats: joining seats an account in one match and issues a connect token. The seat is
/// *reserved* until the game channel connects with that token (and given back if it does not
/// within the token's lifetime), *taken* while the player is in the match (connected, or away
/// within the reconnect grace), and released when the player leaves or its grace runs out.
/// A match is full when its seats are. Thread-safe: one mutex over the tables; MatchHost calls
/// post to the match strands and return at once.
///
/// Rotation: when a match ends by itself the registry drops it, gives back its seats (kicking
/// the game connections still up, after the MatchEnded went out), opens the next match of the
/// rotation under a new id with the same name and size, and hands the ended match on.

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/unordered/unordered_flat_map.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "game_channel.h"
#include "match_directory.h"
#include "match_host.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "steady_time.h"

namespace ricochet::server {

struct MatchRegistryConfig {
  /// Tick, snapshots, movement and rules of every match; id, name and max_players set per
  /// match. rules.seed 0: each match draws a random seed when it opens (logged).
  MatchConfig match_defaults;
  std::uint16_t udp_port = 0;  ///< told to joining clients
  proto::Key token_key{};      ///< the server-only key tokens are sealed with
  proto::TimeUs token_lifetime_us = 10 * proto::kMicrosPerSecond;  ///< ≤ 30 s
  std::uint32_t token_timeout_s = 5;  ///< game-channel silence that drops a client
  int max_matches = 256;
  /// Where the matches stream their recordings as they run; null: each hands its whole
  /// recording over when it ends (EndedMatch::recording).
  RecordingFiles* recordings = nullptr;
  /// The clock, in µs, that connect tokens are issued on and seat reservations run out on: the
  /// game channel's, which checks the tokens (steady_now_us). Tests pass fake time.
  std::function<proto::TimeUs()> clock = steady_now_us;
};

class MatchRegistry final : public MatchDirectory, public GameRouter {
 public:
  /// `maps` is the rotation (at least one): every map a match may be played on, in order.
  /// `ended` gets every match that ended by itself (on that match's strand), after the next
  /// match of the rotation opened.
  MatchRegistry(boost::asio::io_context& io, MatchRegistryConfig config, std::vector<Map> maps,
                GameChannel& channel, MatchEndedHandler ended);
  ~MatchRegistry() override;

  /// Opens a match on the rotation's map `map` (0: the first; taken modulo the rotation's size),
  /// at start and through create(); the message says why it could not.
  DirectoryResult<MatchSummary> open(const std::string& name, int max_players, std::size_t map = 0);
  /// The rotation's map after `map`: where a match that ended on `map` is followed.
  std::size_t next_in_rotation(std::size_t map) const { return (map + 1) % maps_.size(); }
  /// The UDP port clients are told, once the channel is bound.
  void set_udp_port(std::uint16_t port);
  /// Refuses joins and creates from now on (graceful shutdown).
  void close();
  /// Every match, for ending them and for metrics.
  std::vector<std::shared_ptr<MatchHost>> hosts() const;
  /// Seats reserved or taken, all matches together.
  std::size_t seats() const;
  /// Reliable messages clients sent though none is defined (dropped).
  std::uint64_t unexpected_reliable() const { return unexpected_reliable_.load(); }

  // MatchDirectory
  std::vector<MatchSummary> list() const override;
  DirectoryResult<MatchSummary> create(const CreateMatchRequest& request) override;
  DirectoryResult<JoinGrant> join(std::uint64_t account, const std::string& username,
                                  std::uint32_t match_id) override;
  DirectoryResult<Done> leave(std::uint64_t account) override;
  DirectoryResult<Done> chat(std::uint64_t account, const std::string& text) override;

  // GameRouter
  void connected(std::uint64_t account, std::uint32_t match_id) override;
  void disconnected(std::uint64_t account, proto::DisconnectReason reason) override;
  void payloads(std::vector<GamePayload> batch) override;
  void reliable(std::uint64_t account, std::vector<std::uint8_t> bytes) override;

 private:
  struct Seat {
    std::uint32_t match_id = 0;
    std::string username;
    bool taken = false;  ///< the game channel connected at least once
    /// While not taken: the newest token's expiry plus its timeout (a handshake accepted just
    /// before the expiry may take that long to finish).
    proto::TimeUs reserved_until = 0;
    std::uint64_t generation = 0;  ///< bumped on every connection, named by SeatReleased
  };

  /// Why no match can be opened now (closed, or at the cap), or nothing. Holds mutex_.
  std::optional<DirectoryError> refuse_open() const;
  /// Gives back reserved seats whose token expired unused. Holds mutex_.
  void expire_reservations(proto::TimeUs now);
  /// A seat that counts: taken, or reserved by a token still usable at `now`.
  static bool holds(const Seat& seat, proto::TimeUs now);
  int seats_in(std::uint32_t match_id, proto::TimeUs now) const;         ///< holds mutex_
  MatchSummary summary(const MatchHost& host, proto::TimeUs now) const;  ///< holds mutex_
  std::shared_ptr<MatchHost> host_of(std::uint64_t account) const;
  /// A match ended by itself (on its strand): drop it, free its seats, open the next one.
  void match_ended(std::uint32_t match_id, EndedMatch ended);
  void release(std::uint64_t account, std::uint32_t match_id, std::uint64_t generation);

  boost::asio::io_context& io_;
  MatchRegistryConfig config_;
  std::vector<Map> maps_;  ///< the rotation, never empty
  GameChannel& channel_;
  MatchEndedHandler ended_;
  mutable std::mutex mutex_;
  struct Hosted {
    std::shared_ptr<MatchHost> host;
    std::size_t map = 0;                                ///< index in the rotation
    std::shared_ptr<const wire::CollisionWorld> world;  ///< what its join replies carry
    std::vector<wire::WeaponSpec> weapons;              ///< and these
  };
  std::map<std::uint32_t, Hosted> hosts_;
  /// By account; open addressing (every datagram received looks its sender's seat up).
  boost::unordered_flat_map<std::uint64_t, Seat> seats_;
  std::uint32_t next_match_id_ = 1;
  std::uint64_t next_generation_ = 1;
  bool closed_ = false;
  std::atomic<std::uint64_t> unexpected_reliable_{0};
};

}  // namespace ricochet::server
