#include "ricochet/loadtest/error_kinds.h"

#include <array>
#include <cctype>
#include <utility>

namespace ricochet::loadtest {

namespace {

bool is_upper_token_char(char c) {
  return (c >= 'A' && c <= 'Z') || c == '_';
}

/// The first run of at least four of [A-Z_] starting with a letter: an ErrorCode name.
std::string error_code_in(std::string_view reason) {
  for (std::size_t i = 0; i < reason.size(); ++i) {
    if (reason[i] < 'A' || reason[i] > 'Z') continue;
    if (i > 0 && std::isalnum(static_cast<unsigned char>(reason[i - 1]))) continue;
    std::size_t end = i;
    while (end < reason.size() && is_upper_token_char(reason[end])) ++end;
    const bool whole =
        end == reason.size() || !std::isalnum(static_cast<unsigned char>(reason[end]));
    if (end - i >= 4 && whole && reason.substr(i, end - i).find('_') != std::string_view::npos) {
      std::string code(reason.substr(i, end - i));
      for (char& c : code) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return code;
    }
    i = end;
  }
  return {};
}

}  // namespace

std::string error_kind(std::string_view reason) {
  if (reason.rfind("gave up", 0) == 0) return "gave_up";
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 11> kPrefixes = {{
      {"timed out connecting", "timeout_connect"},
      {"timed out signing in", "timeout_sign_in"},
      {"timed out joining", "timeout_join"},
      {"timed out in the game handshake", "timeout_handshake"},
      {"control channel lost", "control_lost"},
      {"the control channel is down", "control_lost"},
      {"cannot connect", "connect_failed"},
      {"cannot bind a UDP socket", "udp_socket"},
      {"unusable join reply", "bad_join_reply"},
      {"unusable assignment", "bad_assignment"},  // placement: a find_match reply refused
      {"the ticket expired", "ticket_expired"},   // placement: before the bot could present it
  }};
  for (const auto& [prefix, kind] : kPrefixes) {
    if (reason.rfind(prefix, 0) == 0) return std::string(kind);
  }
  constexpr std::string_view kGameLost = "game channel ended: ";
  if (reason.rfind(kGameLost, 0) == 0) {
    std::string kind = "game_lost_";
    for (const char c : reason.substr(kGameLost.size())) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') break;
      kind += c;
    }
    return kind;
  }
  if (std::string code = error_code_in(reason); !code.empty()) return code;
  if (reason.find("TLS") != std::string_view::npos ||
      reason.find("handshake") != std::string_view::npos) {
    return "tls_failed";
  }
  return "other";
}

}  // namespace ricochet::loadtest
