#include "ricochet/bot/assignment.h"

#include <algorithm>

#include "ricochet/bot/server_trust.h"
#include "ricochet/tools/port_text.h"

namespace ricochet::bot {
namespace {

constexpr std::size_t kTicketBytes = 32;
constexpr std::size_t kSha256HexDigits = 64;
constexpr std::size_t kMaxModeChars = 32;
constexpr std::size_t kMaxMapChars = 64;

bool is_mode_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

bool is_map_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '.' || c == '-';
}

}  // namespace

std::variant<MatchWanted, std::string> parse_match_wanted(std::string_view text) {
  const std::size_t colon = text.find(':');
  MatchWanted wanted;
  wanted.mode = std::string(text.substr(0, colon));
  if (colon != std::string_view::npos) wanted.map = std::string(text.substr(colon + 1));
  if (wanted.mode.empty() || wanted.mode.size() > kMaxModeChars ||
      !std::all_of(wanted.mode.begin(), wanted.mode.end(), is_mode_char)) {
    return "find_match must be MODE or MODE:MAP with MODE 1..32 of [a-z0-9_-], got \"" +
           std::string(text) + "\"";
  }
  if (colon != std::string_view::npos &&
      (wanted.map.empty() || wanted.map.size() > kMaxMapChars ||
       !std::all_of(wanted.map.begin(), wanted.map.end(), is_map_char))) {
    return "find_match's MAP must be 1..64 of [A-Za-z0-9_.-], got \"" + std::string(text) + "\"";
  }
  return wanted;
}

double Assigned::ticket_left_s(proto::TimeUs now) const {
  return static_cast<double>(std::max<proto::TimeUs>(ticket_expires_at_us - now, 0)) /
         static_cast<double>(proto::kMicrosPerSecond);
}

std::variant<Assigned, std::string> read_assignment(const wire::Assignment& assignment,
                                                    proto::TimeUs now) {
  Assigned out;
  if (assignment.ticket().size() != kTicketBytes) {
    return "a ticket of " + std::to_string(assignment.ticket().size()) + " bytes, expected " +
           std::to_string(kTicketBytes);
  }
  out.ticket = assignment.ticket();
  out.match_id = assignment.match_id();
  out.ticket_expires_at_us =
      now + static_cast<proto::TimeUs>(assignment.ticket_expires_in_ms()) * proto::kMicrosPerMilli;
  out.on_this_server = assignment.on_this_server();
  if (out.on_this_server) return out;

  const std::string& connection = assignment.connection();
  const std::size_t colon = connection.rfind(':');
  if (colon == std::string::npos) {
    return "connection must be host:port, got \"" + connection + "\"";
  }
  std::string_view host = std::string_view(connection).substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  } else if (host.find(':') != std::string_view::npos) {
    return "an IPv6 connection must be [address]:port, got \"" + connection + "\"";
  }
  boost::system::error_code error;
  out.host = boost::asio::ip::make_address(std::string(host), error);
  if (error) {
    return "connection's host must be a numeric IP address (the bot resolves no names), got \"" +
           connection + "\"";
  }
  const auto control_port = tools::parse_port(std::string_view(connection).substr(colon + 1));
  if (!control_port) return "connection's port must be 1..65535, got \"" + connection + "\"";
  out.control_port = *control_port;
  if (assignment.game_port() == 0 || assignment.game_port() > 65535) {
    return "game_port must be 1..65535, got " + std::to_string(assignment.game_port());
  }
  out.game_port = static_cast<std::uint16_t>(assignment.game_port());
  const auto fingerprint = normalize_fingerprint(assignment.certificate_sha256());
  if (!fingerprint || assignment.certificate_sha256().size() != kSha256HexDigits) {
    return "certificate_sha256 must be 64 hex digits, got \"" + assignment.certificate_sha256() +
           "\"";
  }
  out.fingerprint = *fingerprint;
  return out;
}

}  // namespace ricochet::bot
