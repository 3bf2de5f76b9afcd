#pragma once
/// GET /fleet's body (admin_http.h): the live fleet directory as JSON, for tools
/// (ricochet-loadtest --fleet) and dashboards ("the other servers of the fleet").
///
///   {"now_ms": 1733500000000,            this server's wall clock when it answered (Unix ms)
///    "self": "rs-…",                     this server's id
///    "servers": [                        every live row, by server_id
///      {"server_id": "rs-…", "self": true,
///       "host": "game1.example.net",     where players and tools reach it
///       "control_port": 7777, "game_port": 7778,
///       "admin_port": 9100,              null: not advertised (admin_advertisement.h)
///       "certificate_sha256": "…",       64 lowercase hex digits (pin it)
///       "version": "…", "capacity": 64, "players": 12,
///       "heartbeat_age_ms": 840,         now_ms less its last heartbeat, as written by its own
///                                        clock: negative when that clock is ahead of this one
///       "started_ms": …, "counted_ms": …,   Unix ms, its own clock (fleet_records.h)
///       "matches": [{"match_id": 1, "mode": "ffa", "map": "foundry", "players": 5,
///                    "capacity": 16, "open": true}, …]}, …]}
///
/// A match listed for a server that is not among the rows (it beat between the two reads) is
/// left out.

#include <string>
#include <string_view>

#include "ricochet/db/fleet_records.h"

namespace ricochet::server {

/// The JSON above; `now_ms` is this server's Unix time in ms, `self_id` its server id.
std::string fleet_json(const db::FleetDirectory& directory, std::string_view self_id,
                       db::UnixMillis now_ms);

}  // namespace ricochet::server
