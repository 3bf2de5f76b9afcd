#pragma once
/// Match rules over any Store: what a valid match record is, who won, the Elo update, lifetime
/// stats, and the leaderboards with their ranks.
///
///   record_match  refuses a record without a uuid (is_match_uuid), with missing or
///                 out-of-range fields, a mode other than
///                 "ffa" or "tdm", a team that does not fit the mode (ffa: all 0; tdm: every
///                 player 1 or 2), team scores in ffa, or an unknown or repeated player
///                 (InvalidMatch); scores may be negative (suicides and team kills cost a
///                 point), counts may not. Otherwise, in one transaction, reads each player's
///                 rating, computes the new ones (rating.h) and the winners and has the store write
///                 it all; but when a match with the record's uuid is already stored, it
///                 writes nothing and answers that match as stored (RecordedMatch::existed), so
///                 that a record written twice (a retry after a commit whose answer was lost, a
///                 result delivered again from the server's outbox) counts once. Winners: ffa,
///                 everyone with the top score; tdm, every player of the team with the top team
///                 score; ties all win. An aborted match (MatchRecord::aborted) is stored, and its
///                 players' kills, deaths, score, shots, hits, damage and time, and the match
///                 itself, count in their lifetime totals (so it lowers a win rate like a match not
///                 won); but it has no winner and every rating stays as it was.
///   leaderboard   best first; equal values share the better rank
///   rank_of       one account's place on a board: 1 + how many entries are strictly better

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/db/records.h"
#include "ricochet/db/refusals.h"
#include "ricochet/db/result.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

/// Characters of a MatchRecord::uuid: 16 bytes as lowercase hex.
inline constexpr std::size_t kMatchUuidChars = 32;
/// A new MatchRecord::uuid: 16 bytes from libsodium's CSPRNG, as 32 lowercase hex digits.
std::string new_match_uuid();
/// Whether `uuid` is 32 lowercase hex digits, as new_match_uuid makes them.
bool is_match_uuid(std::string_view uuid);

struct MatchesOptions {
  /// Matches an account needs before it appears on the win-rate board (at least 1).
  std::int64_t min_matches_for_win_rate = 10;
  OnRefusal on_refusal;  ///< see refusals.h
};

class Matches {
 public:
  /// The store must outlive this object.
  explicit Matches(Store& store, MatchesOptions options = {});

  DbResult<RecordedMatch> record_match(const MatchRecord& match);
  /// Zeros and the initial rating for an account that never played; UnknownAccount if none.
  DbResult<PlayerStats> player_stats(AccountId id);
  /// The first `limit` entries, best first (ties by account id).
  DbResult<std::vector<LeaderboardEntry>> leaderboard(LeaderboardKind kind, int limit);
  /// nullopt when the account is not on the board (no matches, or too few for WinRate).
  DbResult<std::optional<LeaderboardEntry>> rank_of(AccountId id, LeaderboardKind kind);

  const Refusals& refusals() const { return refusals_; }

 private:
  /// The matches an entry of `kind` needs.
  std::int64_t matches_needed(LeaderboardKind kind) const;

  Store& store_;
  MatchesOptions options_;
  Refusals refusals_;
};

}  // namespace ricochet::db
