/// Match record validation (match_validation.h).

#include "match_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace ricochet::db {

namespace {

constexpr std::size_t kMaxNameBytes = 64;    ///< map and mode names
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
  const std::pair<const char*, std::int32_t> counters[] = {{"kills", p.kills},
                                                           {"deaths", p.deaths},
                                                           {"score", p.score},
                                                           {"shots", p.shots},
                                                           {"hits", p.hits}};
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

}  // namespace

std::string check_match(const MatchRecord& match) {
  if (match.players.empty()) return "a match needs at least one player";
  if (auto e = check_name("map", match.map); !e.empty()) return e;
  if (auto e = check_name("mode", match.mode); !e.empty()) return e;
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
