#pragma once
/// What the store keeps: accounts, sessions, matches with per-player results, lifetime stats and
/// ratings. Times are Unix milliseconds passed in by the caller (the store never reads a clock).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ricochet::db {

using AccountId = std::int64_t;
using MatchId = std::int64_t;
using UnixMillis = std::int64_t;

struct Account {
  AccountId id = 0;
  std::string username;  ///< as registered (case kept)
  UnixMillis created_ms = 0;
  std::optional<UnixMillis> last_login_ms;
  bool banned = false;
};

/// An account row with its password hash, for the accounts logic only.
struct AccountCredentials {
  Account account;
  std::string password_hash;  ///< libsodium crypto_pwhash_str output (Argon2id)
};

/// A stored session: only the SHA-256 of the token is kept.
struct SessionRow {
  AccountId account = 0;
  UnixMillis created_ms = 0;
  UnixMillis expires_ms = 0;
};

/// The modes a match record may name.
inline constexpr std::string_view kModeFreeForAll = "ffa";
inline constexpr std::string_view kModeTeamDeathmatch = "tdm";

/// Teams as a match record numbers them (the same numbers as wire::Team).
inline constexpr std::int32_t kNoTeam = 0;   ///< free-for-all
inline constexpr std::int32_t kTeamRed = 1;  ///< team deathmatch
inline constexpr std::int32_t kTeamBlue = 2;

/// One player's result in a match.
struct PlayerResult {
  AccountId account = 0;
  std::int32_t team = kNoTeam;  ///< ffa: kNoTeam; tdm: kTeamRed or kTeamBlue
  std::int32_t kills = 0;
  std::int32_t deaths = 0;
  std::int32_t score = 0;
  std::int32_t shots = 0;
  std::int32_t hits = 0;
  double damage_dealt = 0;  ///< hit points
  double damage_taken = 0;  ///< hit points
  double seconds_played = 0;
};

/// What a match did to one player, decided by the match rules (matches.h) and kept by the store.
struct PlayerOutcome {
  double rating_before = 0;  ///< Elo
  double rating_after = 0;   ///< Elo
  bool won = false;          ///< ffa: had the top score; tdm: on the top team (ties all win)
};

/// The teams' scores of a team deathmatch (both 0 in free-for-all).
struct TeamScores {
  std::int32_t red = 0;
  std::int32_t blue = 0;
};

/// A finished match, written in one transaction with every player's result.
struct MatchRecord {
  /// The match's own name, drawn when it ends (new_match_uuid, matches.h): 16 random bytes as 32
  /// lowercase hex digits. record_match writes a uuid once: a record written again (a retry
  /// after a commit whose answer was lost, a result delivered again from the server's outbox)
  /// finds the match already there.
  std::string uuid;
  std::string map;
  std::string mode{kModeFreeForAll};  ///< kModeFreeForAll or kModeTeamDeathmatch
  UnixMillis started_ms = 0;
  UnixMillis ended_ms = 0;
  std::int32_t tick_rate = 60;  ///< Hz
  /// Stopped before its end (the server was told to stop): what was played is kept and counted
  /// in the lifetime totals, but it decides no winner and moves no rating (matches.h).
  bool aborted = false;
  TeamScores team_scores;  ///< tdm only
  std::vector<PlayerResult> players;
};

/// A match as record_match wrote it: its id and what it did to each player (outcomes[i] is
/// players[i]'s).
struct RecordedMatch {
  MatchId id = 0;
  std::vector<PlayerOutcome> outcomes;
  bool existed = false;  ///< found by its uuid, written before: nothing was written now
};

/// A match as the store keeps it, found by its uuid (Store::find_match): its id, and each
/// player's account and ratings as written (won is not kept per match: false here).
struct StoredMatch {
  MatchId id = 0;
  std::vector<AccountId> accounts;
  std::vector<PlayerOutcome> outcomes;  ///< outcomes[i] is accounts[i]'s
};

/// Lifetime totals of one account.
struct PlayerStats {
  AccountId account = 0;
  std::string username;
  std::int64_t matches = 0;  ///< aborted ones included
  std::int64_t wins = 0;     ///< matches the player won (PlayerOutcome::won)
  std::int64_t kills = 0;
  std::int64_t deaths = 0;
  std::int64_t score = 0;
  std::int64_t shots = 0;
  std::int64_t hits = 0;
  double damage_dealt = 0;
  double damage_taken = 0;
  double seconds_played = 0;
  double rating = 1500;  ///< Elo (see rating.h)
};

enum class LeaderboardKind {
  Rating,   ///< highest Elo first
  Kills,    ///< most lifetime kills first
  WinRate,  ///< wins / matches, only accounts with at least the minimum number of matches
};

struct LeaderboardEntry {
  std::int64_t rank = 0;  ///< 1-based; equal values share the better rank (0 from a Store)
  AccountId account = 0;
  std::string username;
  double value = 0;  ///< rating, kills or win rate
  std::int64_t matches = 0;
};

}  // namespace ricochet::db
