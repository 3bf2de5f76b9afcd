#pragma once
/// The choice of a seat for an assignment, from what the directory holds (placement.h, steps 2
/// to 5 of assign). Pure: no store, no clock.

#include <cstddef>
#include <string_view>
#include <vector>

#include "ricochet/db/fleet_records.h"
#include "ricochet/db/result.h"

namespace ricochet::db {

struct SeatChoice {
  std::size_t server = 0;  ///< index into the servers given
  MatchId match_id = 0;    ///< 0: a new match on that server
  std::string_view map;    ///< the chosen match's map; for a new match, the one asked for
};

/// The live servers, their matches and the seats their open tickets hold → the seat, or
/// NoServerAvailable / UnknownModeOrMap with what was looked for. `map` empty: any map.
DbResult<SeatChoice> choose_seat(const std::vector<GameServerRow>& servers,
                                 const std::vector<DirectoryMatch>& matches,
                                 const std::vector<HeldSeats>& held, std::string_view mode,
                                 std::string_view map);

}  // namespace ricochet::db
