/// A match's seats (roster.h).

#include "roster.h"

#include <algorithm>

namespace ricochet::server {

Player* Roster::find(std::uint64_t account) {
  for (Player& player : players) {
    if (player.account == account) return &player;
  }
  return nullptr;
}

const Player* Roster::find(std::uint64_t account) const {
  return const_cast<Roster*>(this)->find(account);
}

Player* Roster::find_entity(std::uint32_t entity_id) {
  const auto at = std::lower_bound(
      players.begin(), players.end(), entity_id,
      [](const Player& player, std::uint32_t id) { return player.entity_id < id; });
  return at != players.end() && at->entity_id == entity_id ? &*at : nullptr;
}

int Roster::connected_count() const {
  return static_cast<int>(std::count_if(players.begin(), players.end(),
                                        [](const Player& player) { return player.connected; }));
}

std::vector<PlayerScore> Roster::scoreboard() const {
  std::vector<PlayerScore> out = departed;
  for (const Player& player : players) out.push_back(player.score);
  std::sort(out.begin(), out.end(),
            [](const PlayerScore& a, const PlayerScore& b) { return a.entity_id < b.entity_id; });
  return out;
}

}  // namespace ricochet::server
