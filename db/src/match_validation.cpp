/// Match record validation (match_validation.h).

#include "match_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "ricochet/db/matches.h"

namespace ricochet::db {

namespace {

constexpr std::size_t kMaxNameBytes = 64;    ///< map names
constexpr std::int32_t kMaxTickRate = 1000;  ///< Hz

std::string check_name(const char* field, const std::string& value) {
  if (value.empty() || value.size() > kMaxNameBytes)
    return std::string("match ") + field + " must be 1.." + std::to_string(kMaxNameBytes) +
           " bytes, got " + std::to_string(value.size());
  return {};
}

std::string check_player(std::size_t index, const PlayerResult& p) {
  const std::string who =
      "player " + std::to_string(index) + " (account " + std::to_string(p.account) + "): ";
  // The score may be negative: a suicide, a death by the world or a team kill costs a point
  // (server/GAMEPLAY.md, Scoring). The counts cannot be.
  const std::pair<const char*, std::int32_t> counters[] = {
      {"kills", p.kills}, {"deaths", p.deaths}, {"shots", p.shots}, {"hits", p.hits}};
  for (const auto& [name, value] : counters)
    if (value < 0) return who + name + " must be >= 0, got " + std::to_string(value);
  const std::pair<const char*, double> amounts[] = {{"damage_dealt", p.damage_dealt},
                                                    {"damage_taken", p.damage_taken},
                                                    {"seconds_played", p.seconds_played}};
  for (const auto& [name, value] : amounts)
    if (!std::isfinite(value) || value < 0)
      return who + name + " must be a finite number >= 0, got " + std::to_string(value);
  return {};
}

/// The mode, and every team as that mode needs it.
std::string check_teams(const MatchRecord& match) {
  const bool teams = match.mode == kModeTeamDeathmatch;
  if (!teams && match.mode != kModeFreeForAll)
    return "match mode must be \"ffa\" or \"tdm\", got \"" + match.mode + "\"";
  const TeamScores& scores = match.team_scores;
  if (!teams && (scores.red != 0 || scores.blue != 0))
    return "an ffa match has no team scores, got red " + std::to_string(scores.red) + " and blue " +
           std::to_string(scores.blue);
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const std::int32_t team = match.players[i].team;
    const bool fits = teams ? (team == kTeamRed || team == kTeamBlue) : team == kNoTeam;
    if (!fits)
      return "player " + std::to_string(i) + " (account " +
             std::to_string(match.players[i].account) + "): team must be " +
             (teams ? "1 (red) or 2 (blue) in a tdm match" : "0 (none) in an ffa match") +
             ", got " + std::to_string(team);
  }
  return {};
}

}  // namespace

bool is_match_uuid(std::string_view uuid) {
  return uuid.size() == kMatchUuidChars && std::all_of(uuid.begin(), uuid.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

std::string check_match(const MatchRecord& match) {
  if (!is_match_uuid(match.uuid))
    return "match uuid must be 32 lowercase hex digits, got \"" + match.uuid.substr(0, 40) +
           "\" (" + std::to_string(match.uuid.size()) + " bytes)";
  if (match.players.empty()) return "a match needs at least one player";
  if (auto e = check_name("map", match.map); !e.empty()) return e;
  if (auto e = check_teams(match); !e.empty()) return e;
  if (match.ended_ms < match.started_ms)
    return "match ended_ms (" + std::to_string(match.ended_ms) + ") is before started_ms (" +
           std::to_string(match.started_ms) + ")";
  if (match.tick_rate < 1 || match.tick_rate > kMaxTickRate)
    return "match tick_rate must be 1.." + std::to_string(kMaxTickRate) + " Hz, got " +
           std::to_string(match.tick_rate);
  for (std::size_t i = 0; i < match.players.size(); ++i)
    if (auto e = check_player(i, match.players[i]); !e.empty()) return e;
  std::vector<AccountId> ids;
  for (const PlayerResult& p : match.players) ids.push_back(p.account);
  std::sort(ids.begin(), ids.end());
  if (auto twice = std::adjacent_find(ids.begin(), ids.end()); twice != ids.end())
    return "account " + std::to_string(*twice) + " is listed twice in the match";
  return {};
}

}  // namespace ricochet::db
