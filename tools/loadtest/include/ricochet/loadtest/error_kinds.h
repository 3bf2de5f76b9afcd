#pragma once
/// Failure reasons (as bots give them) sorted into a few kinds, counted for the report: the
/// server's error code when the reason names one (login_rate_limited, match_full, server_busy),
/// otherwise what failed (timeout_sign_in, control_lost, game_lost_timed_out, connect_failed).

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace ricochet::loadtest {

/// A short snake_case kind for `reason`; "other" when nothing matches.
std::string error_kind(std::string_view reason);

/// Counts by kind, in name order.
using ErrorCounts = std::map<std::string, std::uint64_t>;

}  // namespace ricochet::loadtest
