#include "ricochet/bot/bot_config.h"

#include <boost/asio/ip/address.hpp>

#include "ricochet/bot/assignment.h"
#include "ricochet/bot/server_trust.h"

namespace ricochet::bot {
bool valid_account_name(const std::string& name) {
  if (name.size() < 3 || name.size() > 24) return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string BotConfig::validate() const {
  boost::system::error_code error;
  boost::asio::ip::make_address(host, error);
  if (error) return "host must be a numeric IPv4 or IPv6 address, got \"" + host + "\"";
  if (control_port == 0) return "control_port must be 1..65535, got 0";
  if (!bind_address.empty()) {
    const auto local = boost::asio::ip::make_address(bind_address, error);
    if (error || local.is_v4() != boost::asio::ip::make_address(host).is_v4()) {
      return "bind_address must be a numeric address of the host's family, got \"" + bind_address +
             "\"";
    }
  }
  if (!fingerprint.empty() && !normalize_fingerprint(fingerprint)) {
    return "fingerprint must be 32 hex pairs separated by ':' (as the server logs it), got \"" +
           fingerprint + "\"";
  }
  if (fingerprint.empty() && trust_file.empty()) {
    return "set fingerprint (pin the server's certificate) or trust_file (trust on first use)";
  }
  if (!valid_account_name(name)) {
    return "name must be 3..24 characters of [A-Za-z0-9_.-], got \"" + name + "\"";
  }
  if (password.size() < 8 || password.size() > 1024) {
    return "password must be 8..1024 bytes, got " + std::to_string(password.size());
  }
  if (!find_match.empty()) {
    const auto wanted = parse_match_wanted(find_match);
    if (const auto* problem = std::get_if<std::string>(&wanted)) return *problem;
    if (match_id != 0) {
      return "find_match and match_id exclude each other (the assignment names the match), got "
             "match_id " +
             std::to_string(match_id);
    }
  }
  if (tick_phases < 0 || tick_phases > 64) {
    return "tick_phases must be 0..64, got " + std::to_string(tick_phases);
  }
  if (!(skill >= 0 && skill <= 1)) return "skill must be 0..1, got " + std::to_string(skill);
  if (!(rebind_after_s >= 0 && rebind_after_s <= 86400)) {
    return "rebind_after_s must be 0..86400, got " + std::to_string(rebind_after_s);
  }
  if (matches < 0) return "matches must be >= 0, got " + std::to_string(matches);
  if (max_reconnect_attempts < 1 || max_reconnect_attempts > 1000) {
    return "max_reconnect_attempts must be 1..1000, got " + std::to_string(max_reconnect_attempts);
  }
  return link.validate();
}

}  // namespace ricochet::bot
