/// Seat choice (seat_choice.h).

#include "seat_choice.h"

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

namespace ricochet::db {

namespace {

/// Seats in use on one server: its players and the seats its open tickets hold.
struct ServerLoad {
  std::int64_t occupied = 0;
  std::int64_t capacity = 1;
  std::int64_t free() const { return capacity - occupied; }
};

/// a is less loaded than b: occupied / capacity compared without division.
bool less_loaded(const ServerLoad& a, const ServerLoad& b) {
  return a.occupied * b.capacity < b.occupied * a.capacity;
}

std::string wanted(std::string_view mode, std::string_view map) {
  std::string text = "mode '" + std::string(mode) + "'";
  if (!map.empty()) text += " on map '" + std::string(map) + "'";
  return text;
}

}  // namespace

DbResult<SeatChoice> choose_seat(const std::vector<GameServerRow>& servers,
                                 const std::vector<DirectoryMatch>& matches,
                                 const std::vector<HeldSeats>& held, std::string_view mode,
                                 std::string_view map) {
  if (servers.empty())
    return DbError{DbErrorCode::NoServerAvailable,
                   "no live game server (none has sent a heartbeat within the TTL); retry later"};
  std::map<std::string_view, std::size_t> index;
  std::vector<ServerLoad> load(servers.size());
  for (std::size_t i = 0; i < servers.size(); ++i) {
    index.emplace(servers[i].server_id, i);
    load[i] = {servers[i].players, servers[i].capacity};
  }
  std::map<std::pair<std::string_view, MatchId>, std::int64_t> held_by_match;
  for (const HeldSeats& h : held) {
    const auto it = index.find(h.server_id);
    if (it == index.end()) continue;  // a server that is not live
    load[it->second].occupied += h.seats;
    held_by_match[{h.server_id, h.match_id}] += h.seats;
  }

  // Step 3: the fullest open match with room (noting which servers host the mode and map).
  struct Best {
    bool found = false;
    std::size_t server = 0;
    const HostedMatch* match = nullptr;
    std::int64_t occupied = 0;  ///< the match's
  } best_match;
  std::set<std::string_view> hosts;  // the servers hosting the mode (and map)
  for (const DirectoryMatch& d : matches) {
    const auto it = index.find(d.server_id);
    if (it == index.end() || d.match.mode != mode || (!map.empty() && d.match.map != map)) continue;
    const std::size_t s = it->second;
    hosts.insert(d.server_id);
    if (!d.match.open || load[s].free() <= 0) continue;
    const auto h = held_by_match.find({d.server_id, d.match.match_id});
    const std::int64_t occupied = d.match.players + (h == held_by_match.end() ? 0 : h->second);
    if (occupied >= d.match.capacity) continue;
    // Fullest first, then the least loaded server; ties keep the first (by server id, match id).
    const bool better =
        !best_match.found || occupied > best_match.occupied ||
        (occupied == best_match.occupied && less_loaded(load[s], load[best_match.server]));
    if (better) best_match = {true, s, &d.match, occupied};
  }
  if (best_match.found)
    return SeatChoice{best_match.server, best_match.match->match_id, best_match.match->map};
  if (hosts.empty())
    return DbError{DbErrorCode::UnknownModeOrMap, "no live game server hosts " + wanted(mode, map) +
                                                      " (" + std::to_string(servers.size()) +
                                                      " live)"};
  // Step 4: a new match on the hosting server with the most free seats.
  std::optional<std::size_t> best_new;
  for (const std::string_view server_id : hosts) {
    const std::size_t s = index.at(server_id);
    if (load[s].free() <= 0) continue;
    const bool better =
        !best_new || load[s].free() > load[*best_new].free() ||
        (load[s].free() == load[*best_new].free() && less_loaded(load[s], load[*best_new]));
    if (better) best_new = s;
  }
  if (best_new) return SeatChoice{*best_new, 0, map};
  return DbError{DbErrorCode::NoServerAvailable,
                 "every live game server hosting " + wanted(mode, map) + " is full (" +
                     std::to_string(hosts.size()) + " of " + std::to_string(servers.size()) +
                     " live); retry later"};
}

}  // namespace ricochet::db
