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
/// Limits (SeatLimits; PROTOCOL.md "Limits"): seats held from one address (proto::HostKey of the
/// control connection's peer), seats of one match reserved and not yet connected (the oldest
/// unused for a second gives way to a new join), matches
/// created per account and server-wide (open at once, and per minute). A match created over the
/// control channel is closed once it has had no seat for `empty_match_close_after_us`; the
/// matches opened at start and their rotation stay. Refusals are counted by reason and logged
/// once per episode.
///
/// Rotation: when a match ends by itself the registry drops it, gives back its seats (kicking
/// the game connections still up, after the MatchEnded went out), opens the next match of the
/// rotation under a new id with the same name and size, and hands the ended match on.

#include <array>
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

#include "chat_limiter.h"
#include "episode_log.h"
#include "game_channel.h"
#include "match_directory.h"
#include "match_host.h"
#include "ricochet/proto/token_bucket.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "steady_time.h"

namespace ricochet::server {

/// What one address, one match and one account may hold; defaults as a public server runs.
struct SeatLimits {
  /// Seats (reserved or taken, all matches together) held from one proto::HostKey.
  int seats_per_address = 8;
  /// Seats of one match reserved by a token and not yet connected over the game channel; never
  /// more than half the match's seats (at least one). At the bound, a join takes the place of
  /// the oldest reservation unused for a second (whose token then finds no seat), or is refused.
  int reserved_seats_per_match = 4;
  int created_matches = 32;             ///< matches created over the control channel, open at once
  int created_matches_per_account = 1;  ///< of those, created by one account
  double creates_per_minute = 30;       ///< match creations, the whole server (burst: 10)
  double creates_per_account_per_minute = 2;  ///< match creations by one account (burst: 1)
  /// A created match with no seat held this long is closed, in µs.
  proto::TimeUs empty_match_close_after_us = 60 * proto::kMicrosPerSecond;
};

/// Why the registry refused a seat or a match (ricochet_match_limit_refused_total{reason}).
enum class SeatRefusal {
  AddressSeats,       ///< the address holds seats_per_address
  ReservedSeats,      ///< the match has reserved_seats_per_match seats still connecting
  CreatedMatches,     ///< created_matches are open
  AccountMatches,     ///< the account has created_matches_per_account open
  CreateRate,         ///< creates_per_minute spent
  AccountCreateRate,  ///< creates_per_account_per_minute spent
};
inline constexpr std::size_t kSeatRefusalCount =
    static_cast<std::size_t>(SeatRefusal::AccountCreateRate) + 1;
/// "address_seats", "reserved_seats", "created_matches", "account_matches", "create_rate",
/// "account_create_rate".
const char* name(SeatRefusal refusal);

struct MatchRegistryConfig {
  /// Tick, snapshots, movement and rules of every match; id, name and max_players set per
  /// match. rules.seed 0: each match draws a random seed when it opens (logged).
  MatchConfig match_defaults;
  std::uint16_t udp_port = 0;  ///< told to joining clients
  proto::Key token_key{};      ///< the server-only key tokens are sealed with
  proto::TimeUs token_lifetime_us = 10 * proto::kMicrosPerSecond;  ///< ≤ 30 s
  std::uint32_t token_timeout_s = 5;  ///< game-channel silence that drops a client
  /// A join within this long of the account's newest token, while no game connection has used
  /// it, gets that token again (PROTOCOL.md JoinMatch): an account mints at most one token per
  /// this interval, however many sessions ask (never one that expired). 0: a new token each join.
  proto::TimeUs token_reuse_us = proto::kMicrosPerSecond;
  int max_matches = 256;
  /// Chat's rate limits (the server's, shared with nothing else); nullptr: chat is not limited
  /// (tests of the registry alone).
  ChatLimiter* chat_limiter = nullptr;
  SeatLimits limits;
  /// Logs each limit's refusals once per episode; nullptr: refusals are only counted.
  EpisodeLog* episodes = nullptr;
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
  /// `creator`: the account that created it (or the match it follows), 0 for the server's own;
  /// only created matches are counted against the creation limits and closed when empty.
  DirectoryResult<MatchSummary> open(const std::string& name, int max_players, std::size_t map = 0,
                                     std::uint64_t creator = 0);
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
  /// Closes the created matches that have had no seat for empty_match_close_after_us; each is
  /// handed to the MatchEndedHandler like a match that ended. Also done on every list, create
  /// and join; the server calls it every few seconds.
  void close_empty_matches();
  std::uint64_t refused(SeatRefusal refusal) const;
  /// Takes the account out of its match, whichever session plays it (a ban): the seat given
  /// back, its token forgotten, the game connection ended with `reason`, its entity gone for
  /// good. False when it held no seat.
  bool remove(std::uint64_t account, proto::DisconnectReason reason);
  std::uint64_t empty_matches_closed() const { return empty_matches_closed_.load(); }
  /// Seats that open placement tickets hold, by match (the directory's held_seats, read at each
  /// heartbeat): a join without a ticket counts them as taken.
  void set_held_seats(boost::unordered_flat_map<std::uint32_t, int> held);

  // MatchDirectory
  std::vector<MatchSummary> list() const override;
  DirectoryResult<MatchSummary> create(const CreateMatchRequest& request) override;
  DirectoryResult<JoinGrant> join(std::uint64_t account, const std::string& username,
                                  std::uint32_t match_id, const JoinOrigin& origin) override;
  std::optional<std::uint32_t> rejoin(std::uint64_t account, const JoinOrigin& origin) override;
  DirectoryResult<Done> leave(std::uint64_t account, std::uint64_t session) override;
  DirectoryResult<Done> chat(std::uint64_t account, std::uint64_t session,
                             const std::string& text) override;

  // GameRouter
  void connected(std::uint64_t account, std::uint32_t match_id) override;
  void disconnected(std::uint64_t account, proto::DisconnectReason reason) override;
  void payloads(std::vector<GamePayload> batch) override;
  void reliable(std::uint64_t account, std::vector<std::uint8_t> bytes) override;

 private:
  struct Seat {
    std::uint32_t match_id = 0;
    std::string username;
    bool taken = false;      ///< the game channel connected at least once
    bool connected = false;  ///< its game connection is up now
    /// While not taken: the newest token's expiry plus its timeout (a handshake accepted just
    /// before the expiry may take that long to finish).
    proto::TimeUs reserved_until = 0;
    std::uint64_t generation = 0;   ///< bumped on every connection, named by SeatReleased
    proto::HostKey host;            ///< where the newest join came from
    std::uint64_t session = 0;      ///< the control session that plays the account
    proto::TimeUs reserved_at = 0;  ///< the first join (joining again does not move it)
    /// What `session` signed in with: a resume with it takes the seat back (rejoin).
    std::string session_token = {};
  };

  /// Why no match can be opened now (closed, at the cap, or `creator` at a created-match
  /// limit), or nothing. Holds mutex_.
  std::optional<DirectoryError> refuse_open(std::uint64_t creator, proto::TimeUs now);
  /// Why `origin` may not take a new seat in `match_id` now, or nothing. Holds mutex_.
  std::optional<DirectoryError> refuse_seat(std::uint32_t match_id, int max_players,
                                            const JoinOrigin& origin, proto::TimeUs now);
  /// Counts a refusal, logs its episode and returns the error. Holds mutex_.
  DirectoryError refuse(SeatRefusal refusal, const std::string& key, DirectoryErrorCode code,
                        std::string message, proto::TimeUs now);
  /// Takes the created matches empty for too long out of hosts_. Holds mutex_.
  std::vector<std::shared_ptr<MatchHost>> take_empty_matches(proto::TimeUs now);
  /// Ends matches taken out by take_empty_matches (lock released).
  void end_empty_matches(std::vector<std::shared_ptr<MatchHost>> hosts);
  DirectoryResult<JoinGrant> join_locked(std::uint64_t account, const std::string& username,
                                         std::uint32_t match_id, const JoinOrigin& origin,
                                         proto::TimeUs now);  ///< holds mutex_
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
  /// The account's connect token for `match_id`: the one issued within token_reuse_us if no
  /// connection used it yet, else a new one. Holds mutex_.
  proto::TokenGrant token_for(std::uint64_t account, std::uint32_t match_id, proto::TimeUs now);

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
    std::uint64_t creator = 0;         ///< the account that created it; 0: the server's own
    proto::TimeUs last_seated_at = 0;  ///< when it was last seen with a seat held (or opened)
  };
  std::map<std::uint32_t, Hosted> hosts_;
  /// By account; open addressing (every datagram received looks its sender's seat up).
  boost::unordered_flat_map<std::uint64_t, Seat> seats_;
  boost::unordered_flat_map<std::uint32_t, int> held_by_tickets_;  ///< set_held_seats()
  /// Each account's newest token while it may be given again (token_for); forgotten when the
  /// account connects or leaves, or the reuse window passes.
  struct IssuedToken {
    std::uint32_t match_id = 0;
    proto::TokenGrant grant;
    proto::TimeUs issued_at = 0;
  };
  boost::unordered_flat_map<std::uint64_t, IssuedToken> issued_tokens_;
  std::uint32_t next_match_id_ = 1;
  std::uint64_t next_generation_ = 1;
  bool closed_ = false;
  std::atomic<std::uint64_t> unexpected_reliable_{0};
  proto::TokenBucket creates_;  ///< limits.creates_per_minute
  /// limits.creates_per_account_per_minute, by account; full buckets are forgotten.
  std::map<std::uint64_t, proto::TokenBucket> account_creates_;
  std::array<std::atomic<std::uint64_t>, kSeatRefusalCount> refused_{};
  std::atomic<std::uint64_t> empty_matches_closed_{0};
};

}  // namespace ricochet::server
