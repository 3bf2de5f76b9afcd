#pragma once
/// The match id a dashboard URL names (/matches/ID/...): untrusted text from outside.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace ricochet::server::web {

/// A match id (MatchConfig::id) from `text`: 1..10 decimal digits, no sign, no leading zero,
/// 1..4294967295. Otherwise why not, to log once and count ("match id must be 1..10 digits, got
/// 11 bytes"); the text itself is never echoed.
std::variant<std::uint32_t, std::string> parse_match_id(std::string_view text);

}  // namespace ricochet::server::web
