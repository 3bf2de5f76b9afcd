#pragma once
/// What the control channel asks of the matches: list, create, join, leave, chat. Implemented by
/// the server (server.cpp) over the matches it hosts; control sessions code against this
/// interface only, and tests pass a fake. Thread-safe; every call returns at once (joining
/// reserves a seat and issues a connect token; the player enters the match when its game
/// channel connects).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/proto/address.h"
#include "ricochet/proto/quantize.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/wire/game.pb.h"
#include "ricochet/wire/world.pb.h"

namespace ricochet::server {

struct MatchSummary {
  std::uint32_t id = 0;
  std::string name;
  std::string mode;  ///< "ffa" (free-for-all) or "tdm" (team deathmatch): [matches] mode
  std::string map;   ///< the map's name
  int players = 0;   ///< seated: connected plus reserved plus reconnecting
  int max_players = 0;
};

/// The creator of a match a placement ticket opened (a ticket for a new match): no account's.
/// The fleet chose to open it, not the player, so it is bound by the server-wide limits only
/// (matches, created matches open, creations a minute) and closes when empty like a created
/// match; the account is bound by its find_match rate. Account ids never reach it.
inline constexpr std::uint64_t kPlacementCreator = UINT64_MAX;

struct CreateMatchRequest {
  std::string name;      ///< 1..32 printable characters
  int max_players = 16;  ///< 1..64
  std::string map;       ///< a loaded map's name; empty: the rotation's first
  /// The account asking: its created matches are counted and its creations rate-limited; or
  /// kPlacementCreator.
  std::uint64_t creator = 0;
};

/// Where a join comes from: what the seat limits count under.
struct JoinOrigin {
  proto::HostKey host;        ///< the control connection's peer (proto::host_key)
  std::uint64_t session = 0;  ///< the control connection's id: one session plays the account
  /// The session token the control connection signed in (or resumed) with: a resume with the
  /// same token on a new connection takes the seat back (MatchDirectory::rejoin).
  std::string session_token = {};
  /// Joined with a placement ticket: the seats open tickets hold in the match (the ticket's own
  /// among them until the directory is next read) do not count against it.
  bool placed = false;
};

/// Everything the client needs to open the game channel.
struct JoinGrant {
  std::uint32_t match_id = 0;
  std::uint16_t udp_port = 0;
  proto::TokenGrant token;
  proto::QuantizationSpec quantization;  ///< what the client builds its snapshot decoder from
  int tick_rate_hz = 60;
  int snapshot_rate_hz = 60;
  /// The map's collision world and movement rules, for prediction; nullptr: none is sent.
  std::shared_ptr<const wire::CollisionWorld> world;
  std::vector<wire::WeaponSpec> weapons;  ///< the match's, rifle first (weapon_specs())
};

enum class DirectoryErrorCode {
  MatchNotFound,
  MatchFull,
  AlreadyInMatch,  ///< leave first (joining the same match again re-issues a token instead)
  NotInMatch,
  InvalidRequest,  ///< a field out of range; the message names it
  TooManyMatches,  ///< the server, or the account, has its most matches open
  ShuttingDown,
  RateLimited,        ///< over a rate limit (chat: ChatLimiter); this request was dropped
  AddressSeatLimit,   ///< the joining address holds its most seats (all matches together)
  CreateRateLimited,  ///< matches created too fast, by the account or the whole server
};
inline const char* name(DirectoryErrorCode code) {
  switch (code) {
    case DirectoryErrorCode::MatchNotFound:
      return "match_not_found";
    case DirectoryErrorCode::MatchFull:
      return "match_full";
    case DirectoryErrorCode::AlreadyInMatch:
      return "already_in_match";
    case DirectoryErrorCode::NotInMatch:
      return "not_in_match";
    case DirectoryErrorCode::InvalidRequest:
      return "invalid_request";
    case DirectoryErrorCode::TooManyMatches:
      return "too_many_matches";
    case DirectoryErrorCode::ShuttingDown:
      return "shutting_down";
    case DirectoryErrorCode::RateLimited:
      return "rate_limited";
    case DirectoryErrorCode::AddressSeatLimit:
      return "address_seat_limit";
    case DirectoryErrorCode::CreateRateLimited:
      return "create_rate_limited";
  }
  return "unknown";
}

struct DirectoryError {
  DirectoryErrorCode code;
  std::string message;  ///< what was expected and what came
};

/// A value or the reason there is none.
template <class T>
using DirectoryResult = std::variant<T, DirectoryError>;
struct Done {};

class MatchDirectory {
 public:
  virtual ~MatchDirectory() = default;
  virtual std::vector<MatchSummary> list() const = 0;
  virtual DirectoryResult<MatchSummary> create(const CreateMatchRequest& request) = 0;
  /// Seats the account in the match (keeping its place if it was there within the reconnect
  /// grace) and issues a fresh connect token. One session plays an account: a join of the
  /// account's match from another session moves the seat to that session (the older one's game
  /// connection is kicked; its leave is refused with NotInMatch).
  virtual DirectoryResult<JoinGrant> join(std::uint64_t account, const std::string& username,
                                          std::uint32_t match_id, const JoinOrigin& origin) = 0;
  /// A resumed control connection back in its match (PROTOCOL.md, resume, "Back in the match"):
  /// when the account holds a seat joined (or taken back) from a connection signed in with
  /// `origin.session_token`, the seat is played from `origin.session` from now on, its game
  /// connection untouched; returns the match's id. Nothing when the account holds no seat, or
  /// another sign-in (another token) plays it: that one is not taken over.
  virtual std::optional<std::uint32_t> rejoin(std::uint64_t account, const JoinOrigin& origin) = 0;
  /// Gives the account's seat up, when `session` holds it.
  virtual DirectoryResult<Done> leave(std::uint64_t account, std::uint64_t session) = 0;
  /// Echoed to every player of the account's match over the game channel's reliable messages,
  /// within the chat rate limits (RateLimited beyond them). Only from the `session` that plays
  /// the account, and while its game connection is up (NotInMatch otherwise: nobody would see
  /// the line as coming from it).
  virtual DirectoryResult<Done> chat(std::uint64_t account, std::uint64_t session,
                                     const std::string& text) = 0;
};

}  // namespace ricochet::server
