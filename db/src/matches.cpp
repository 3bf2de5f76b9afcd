/// Match rules over a Store (matches.h).

#include "ricochet/db/matches.h"

#include <algorithm>
#include <limits>

#include "match_validation.h"
#include "password.h"
#include "ricochet/db/rating.h"

namespace ricochet::db {

namespace {

DbError invalid_match(std::string message) {
  return DbError{DbErrorCode::InvalidMatch, std::move(message)};
}

/// The score that decides a player's duels: its own (ffa) or its team's (tdm).
std::int32_t deciding_score(const MatchRecord& match, const PlayerResult& player) {
  if (match.mode != kModeTeamDeathmatch) return player.score;
  return player.team == kTeamRed ? match.team_scores.red : match.team_scores.blue;
}

/// Each player's outcome: new ratings by Elo, and a win for everyone with the top deciding
/// score. An aborted match keeps every rating and has no winner.
std::vector<PlayerOutcome> outcomes_of(const MatchRecord& match,
                                       const std::vector<double>& ratings) {
  std::vector<PlayerOutcome> outcomes;
  if (match.aborted) {
    for (const double rating : ratings) outcomes.push_back({rating, rating, false});
    return outcomes;
  }
  std::vector<RatedScore> rated;
  std::int32_t top_score = std::numeric_limits<std::int32_t>::min();
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const std::int32_t score = deciding_score(match, match.players[i]);
    rated.push_back({ratings[i], static_cast<double>(score), match.players[i].team});
    top_score = std::max(top_score, score);
  }
  const std::vector<double> after = updated_ratings(rated);
  for (std::size_t i = 0; i < match.players.size(); ++i)
    outcomes.push_back(
        {ratings[i], after[i], deciding_score(match, match.players[i]) == top_score});
  return outcomes;
}

/// The match as stored, its outcomes in the order of the record's players (won by the same
/// rule as when it was written); InvalidMatch when the stored players are not the record's.
DbResult<RecordedMatch> as_recorded(const MatchRecord& match, const StoredMatch& stored) {
  std::vector<double> before;
  RecordedMatch recorded{stored.id, {}, true};
  for (const PlayerResult& p : match.players) {
    const auto at = std::find(stored.accounts.begin(), stored.accounts.end(), p.account);
    if (at == stored.accounts.end() || stored.accounts.size() != match.players.size())
      return invalid_match("match " + match.uuid + " is stored as match " +
                           std::to_string(stored.id) + " with other players");
    before.push_back(
        stored.outcomes[static_cast<std::size_t>(at - stored.accounts.begin())].rating_before);
  }
  const std::vector<PlayerOutcome> decided = outcomes_of(match, before);
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const auto at =
        std::find(stored.accounts.begin(), stored.accounts.end(), match.players[i].account);
    PlayerOutcome outcome = stored.outcomes[static_cast<std::size_t>(at - stored.accounts.begin())];
    outcome.won = decided[i].won;
    recorded.outcomes.push_back(outcome);
  }
  return recorded;
}

/// Rank 1 is best, and equal values share the better rank: 1 + how many are strictly better.
std::int64_t rank_after(std::int64_t strictly_better) {
  return strictly_better + 1;
}

}  // namespace

std::string new_match_uuid() {
  return random_hex(kMatchUuidChars / 2);
}

Matches::Matches(Store& store, MatchesOptions options)
    : store_(store), options_(std::move(options)), refusals_(options_.on_refusal) {}

DbResult<RecordedMatch> Matches::record_match(const MatchRecord& match) {
  using R = DbResult<RecordedMatch>;
  if (std::string problem = check_match(match); !problem.empty())
    return refusals_(R(invalid_match(std::move(problem))));
  // The ratings are read and written in one transaction, so a match recorded at the same time
  // by another server process on the same database cannot be lost between the two.
  // The uuid is looked up under the write lock, so two writers of one record cannot both miss it.
  RecordedMatch recorded;
  DbResult<MatchId> id = refusals_(atomically(store_, [&]() -> DbResult<MatchId> {
    DbResult<std::optional<StoredMatch>> stored = store_.find_match(match.uuid);
    if (!stored.ok()) return stored.error();
    if (stored.value()) {
      DbResult<RecordedMatch> found = as_recorded(match, *stored.value());
      if (!found.ok()) return found.error();
      recorded = std::move(found).value();
      return recorded.id;
    }
    std::vector<double> ratings;
    for (const PlayerResult& p : match.players) {
      DbResult<std::optional<double>> rating = store_.rating_of(p.account);
      if (!rating.ok() && rating.error().code == DbErrorCode::UnknownAccount)
        return invalid_match("account " + std::to_string(p.account) + " does not exist");
      if (!rating.ok()) return rating.error();
      ratings.push_back(rating.value().value_or(kInitialRating));
    }
    recorded.outcomes = outcomes_of(match, ratings);
    return store_.insert_match(match, recorded.outcomes);
  }));
  if (!id.ok()) return id.error();
  recorded.id = id.value();
  return recorded;
}

DbResult<PlayerStats> Matches::player_stats(AccountId id) {
  return refusals_(store_.player_stats(id));
}

std::int64_t Matches::matches_needed(LeaderboardKind kind) const {
  if (kind != LeaderboardKind::WinRate) return 1;
  return std::max<std::int64_t>(options_.min_matches_for_win_rate, 1);
}

DbResult<std::vector<LeaderboardEntry>> Matches::leaderboard(LeaderboardKind kind, int limit) {
  DbResult<std::vector<LeaderboardEntry>> board =
      refusals_(store_.leaderboard(kind, limit, matches_needed(kind)));
  if (!board.ok()) return board;
  std::vector<LeaderboardEntry>& entries = board.value();
  // Best first: an entry's strictly better ones are all those before the first of its value.
  std::int64_t better = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i > 0 && entries[i].value != entries[i - 1].value) better = static_cast<std::int64_t>(i);
    entries[i].rank = rank_after(better);
  }
  return board;
}

DbResult<std::optional<LeaderboardEntry>> Matches::rank_of(AccountId id, LeaderboardKind kind) {
  using R = DbResult<std::optional<LeaderboardEntry>>;
  const std::int64_t needed = matches_needed(kind);
  R entry = refusals_(store_.board_entry(id, kind));
  if (!entry.ok()) return entry;
  if (!entry.value() || entry.value()->matches < needed) return R(std::nullopt);
  const DbResult<std::int64_t> better =
      refusals_(store_.count_better(kind, entry.value()->value, needed));
  if (!better.ok()) return better.error();
  entry.value()->rank = rank_after(better.value());
  return entry;
}

}  // namespace ricochet::db
