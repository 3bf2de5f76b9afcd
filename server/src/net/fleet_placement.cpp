#include "fleet_placement.h"

#include <array>
#include <iterator>

#include "ricochet/proto/crypto.h"

namespace ricochet::server {
namespace {

constexpr std::string_view kHexDigits = "0123456789abcdef";

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

std::string to_hex(std::span<const std::uint8_t> bytes) {
  std::string hex;
  hex.reserve(bytes.size() * 2);
  for (std::uint8_t byte : bytes) {
    hex += kHexDigits[byte >> 4];
    hex += kHexDigits[byte & 0xF];
  }
  return hex;
}

}  // namespace

const char* name(TicketResult result) {
  switch (result) {
    case TicketResult::Assigned:
      return "assigned";
    case TicketResult::NoServerAvailable:
      return "no_server_available";
    case TicketResult::UnknownModeOrMap:
      return "unknown_mode_or_map";
    case TicketResult::RateLimited:
      return "rate_limited";
    case TicketResult::InvalidRequest:
      return "invalid_request";
    case TicketResult::ServerBusy:
      return "server_busy";
    case TicketResult::Failed:
      return "failed";
  }
  return "unknown";
}

const char* name(HeartbeatOutcome outcome) {
  switch (outcome) {
    case HeartbeatOutcome::Written:
      return "written";
    case HeartbeatOutcome::Failed:
      return "failed";
  }
  return "unknown";
}

bool FindMatchLimiter::take(std::uint64_t account, proto::TimeUs now) {
  prune(now);
  auto [it, added] = buckets_.try_emplace(account, per_second_, kBurst, now);
  return it->second.take(now);
}

void FindMatchLimiter::prune(proto::TimeUs now) {
  if (buckets_.size() < kPruneAt) return;
  for (auto it = buckets_.begin(); it != buckets_.end();) {
    it = it->second.full(now) ? buckets_.erase(it) : std::next(it);
  }
}

std::string ticket_bytes(std::string_view hex) {
  std::string bytes;
  bytes.reserve(hex.size() / 2);
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    bytes += static_cast<char>(hex_value(hex[i]) * 16 + hex_value(hex[i + 1]));
  }
  return bytes;
}

std::optional<std::string> ticket_hex(std::string_view bytes) {
  if (bytes.size() != kTicketBytes) return std::nullopt;
  return to_hex({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()});
}

std::string draw_server_id() {
  std::array<std::uint8_t, 8> random{};
  proto::fill_random(random);
  return "rs-" + to_hex(random);
}

}  // namespace ricochet::server
