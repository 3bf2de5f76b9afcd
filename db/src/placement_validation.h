#pragma once
/// What a valid directory row, hosted match and placement request are, checked before anything is
/// written or read (placement.h). Each check is empty when the value is valid, otherwise what is
/// wrong with it, naming the field, what was expected and what came.

#include <string>
#include <string_view>
#include <vector>

#include "ricochet/db/fleet_records.h"

namespace ricochet::db {

/// A server id: 1–64 of [A-Za-z0-9_-].
std::string check_server_id(std::string_view server_id);
/// A mode: 1–32 of [a-z0-9_-].
std::string check_mode(std::string_view mode);
/// A map: 1–64 printable ASCII characters other than space.
std::string check_map(std::string_view map);
/// The row (its heartbeat_ms is the caller's) and its matches: at most kMaxHostedMatches, ids
/// unique.
std::string check_heartbeat(const GameServerRow& server, const std::vector<HostedMatch>& matches);

inline constexpr std::size_t kMaxHostedMatches = 4096;

}  // namespace ricochet::db
