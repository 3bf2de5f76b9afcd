/// The match id of a dashboard URL (match_id.h).

#include "match_id.h"

#include <algorithm>
#include <charconv>

namespace ricochet::server::web {

std::variant<std::uint32_t, std::string> parse_match_id(std::string_view text) {
  if (text.empty() || text.size() > 10) {
    return "match id must be 1..10 digits, got " + std::to_string(text.size()) + " bytes";
  }
  if (!std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return std::string("match id must be decimal digits only");
  }
  if (text.front() == '0') return std::string("match id must be 1 or more, without leading zeros");
  std::uint32_t id = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (error != std::errc{} || end != text.data() + text.size()) {
    return std::string("match id must be at most 4294967295");
  }
  return id;
}

}  // namespace ricochet::server::web
