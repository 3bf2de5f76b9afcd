/// Directory row and placement request validation (placement_validation.h).

#include "placement_validation.h"

#include <cstdint>
#include <unordered_set>

namespace ricochet::db {

namespace {

constexpr std::size_t kMaxServerIdBytes = 64;
constexpr std::size_t kMaxHostBytes = 253;  ///< a DNS name's limit
constexpr std::size_t kMaxVersionBytes = 64;
constexpr std::size_t kMaxModeBytes = 32;
constexpr std::size_t kMaxMapBytes = 64;
constexpr std::size_t kSha256HexDigits = 64;
constexpr std::int32_t kMaxSeats = 1'000'000;  ///< per server or match

bool is_lower_alnum(char c) {
  return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
}
bool is_lower_hex(char c) {
  return (c >= 'a' && c <= 'f') || (c >= '0' && c <= '9');
}
bool is_alnum(char c) {
  return is_lower_alnum(c) || (c >= 'A' && c <= 'Z');
}
bool is_visible(char c) {
  return c > ' ' && c < 0x7f;
}

/// `field` must be 1..max_bytes characters each accepted by `allowed`, described as `what`.
template <class Allowed>
std::string check_text(const char* field, std::string_view value, std::size_t max_bytes,
                       Allowed allowed, const char* what) {
  if (value.empty() || value.size() > max_bytes)
    return std::string(field) + " must be 1.." + std::to_string(max_bytes) + " bytes, got " +
           std::to_string(value.size());
  for (const char c : value)
    if (!allowed(c))
      return std::string(field) + " must be " + what + ", got the byte " +
             std::to_string(static_cast<unsigned char>(c)) + " in '" +
             std::string(value.substr(0, 64)) + "'";
  return {};
}

std::string check_range(const char* field, std::int64_t value, std::int64_t min, std::int64_t max) {
  if (value >= min && value <= max) return {};
  return std::string(field) + " must be " + std::to_string(min) + ".." + std::to_string(max) +
         ", got " + std::to_string(value);
}

std::string check_match(const HostedMatch& m) {
  const std::string which = "match " + std::to_string(m.match_id) + ": ";
  std::string problem = check_range("match_id", m.match_id, 1, INT64_MAX);
  if (problem.empty()) problem = check_mode(m.mode);
  if (problem.empty()) problem = check_map(m.map);
  if (problem.empty()) problem = check_range("capacity", m.capacity, 1, kMaxSeats);
  if (problem.empty()) problem = check_range("players", m.players, 0, m.capacity);
  return problem.empty() ? problem : which + problem;
}

}  // namespace

std::string check_server_id(std::string_view server_id) {
  return check_text(
      "server_id", server_id, kMaxServerIdBytes,
      [](char c) { return is_alnum(c) || c == '_' || c == '-'; }, "letters, digits, '_' or '-'");
}

std::string check_mode(std::string_view mode) {
  return check_text(
      "mode", mode, kMaxModeBytes, [](char c) { return is_lower_alnum(c) || c == '_' || c == '-'; },
      "lowercase letters, digits, '_' or '-'");
}

std::string check_map(std::string_view map) {
  return check_text("map", map, kMaxMapBytes, is_visible, "printable ASCII without spaces");
}

std::string check_heartbeat(const GameServerRow& server, const std::vector<HostedMatch>& matches) {
  std::string problem = check_server_id(server.server_id);
  // A DNS name, an IPv4 address or an IPv6 address (hex digits and ':').
  if (problem.empty())
    problem = check_text(
        "host", server.host, kMaxHostBytes,
        [](char c) { return is_alnum(c) || c == '.' || c == '-' || c == ':'; },
        "a DNS name or an IP address");
  if (problem.empty()) problem = check_range("control_port", server.control_port, 1, 65535);
  if (problem.empty()) problem = check_range("game_port", server.game_port, 1, 65535);
  if (problem.empty()) problem = check_range("admin_port", server.admin_port, 0, 65535);
  if (problem.empty() && server.certificate_sha256.size() != kSha256HexDigits)
    problem = "certificate_sha256 must be " + std::to_string(kSha256HexDigits) +
              " hex digits, got " + std::to_string(server.certificate_sha256.size());
  if (problem.empty())
    problem = check_text("certificate_sha256", server.certificate_sha256, kSha256HexDigits,
                         is_lower_hex, "lowercase hex digits");
  if (problem.empty())
    problem = check_text(
        "version", server.version, kMaxVersionBytes, [](char c) { return c >= ' ' && c < 0x7f; },
        "printable ASCII");
  if (problem.empty()) problem = check_range("capacity", server.capacity, 1, kMaxSeats);
  if (problem.empty()) problem = check_range("players", server.players, 0, server.capacity);
  if (problem.empty()) problem = check_range("started_ms", server.started_ms, 0, INT64_MAX);
  if (problem.empty() && matches.size() > kMaxHostedMatches)
    problem = "a server may list at most " + std::to_string(kMaxHostedMatches) + " matches, got " +
              std::to_string(matches.size());
  std::unordered_set<MatchId> ids;
  for (const HostedMatch& m : matches) {
    if (!problem.empty()) break;
    problem = check_match(m);
    if (problem.empty() && !ids.insert(m.match_id).second)
      problem = "match " + std::to_string(m.match_id) + " is listed twice";
  }
  return problem.empty() ? problem
                         : "game server '" + server.server_id.substr(0, 64) + "': " + problem;
}

}  // namespace ricochet::db
