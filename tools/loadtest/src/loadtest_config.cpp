#include "ricochet/loadtest/loadtest_config.h"

#include <algorithm>
#include <boost/asio/ip/address.hpp>
#include <charconv>
#include <cmath>

#include "ricochet/bot/assignment.h"
#include "ricochet/bot/bot_config.h"
#include "ricochet/tools/port_text.h"

namespace ricochet::loadtest {

namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// The prefix makes names <prefix>s<step>-<k>, or <prefix>s<step>.<server>-<k> with several
/// servers: the longest, of step 99, server 64 and bot 99999, must be an account name.
bool valid_prefix(const std::string& name) {
  return !name.empty() && name.size() <= 12 && bot::valid_account_name(name + "s99.64-99999");
}

bool is_ipv4(const std::string& address) {
  boost::system::error_code error;
  boost::asio::ip::make_address_v4(address, error);
  return !error;
}

}  // namespace

const char* name(ServerProc mode) {
  switch (mode) {
    case ServerProc::Off:
      return "off";
    case ServerProc::Auto:
      return "auto";
  }
  return "unknown";
}

std::optional<ServerProc> parse_server_proc(std::string_view text) {
  if (text == "off") return ServerProc::Off;
  if (text == "auto") return ServerProc::Auto;
  return std::nullopt;
}

std::string ServerEndpoint::label() const {
  return host + ":" + std::to_string(control_port);
}

std::variant<std::vector<ServerEndpoint>, std::string> parse_servers(
    const std::string& text, std::uint16_t default_control_port, std::uint16_t default_admin_port) {
  std::vector<ServerEndpoint> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string entry = text.substr(start, comma - start);
    start = comma + 1;
    const std::string where = "server " + std::to_string(out.size() + 1) + " (\"" + entry + "\"): ";
    ServerEndpoint server;
    server.control_port = default_control_port;
    server.admin_port = default_admin_port;
    const std::size_t first = entry.find(':');
    server.host = entry.substr(0, first);
    if (!is_ipv4(server.host)) return where + "expected a numeric IPv4 address";
    if (first != std::string::npos) {
      const std::size_t second = entry.find(':', first + 1);
      const auto control = tools::parse_port(std::string_view(entry).substr(
          first + 1, second == std::string::npos ? std::string::npos : second - first - 1));
      if (!control) return where + "expected a control port 1..65535 after the address";
      server.control_port = *control;
      if (second != std::string::npos) {
        const auto admin = tools::parse_port(std::string_view(entry).substr(second + 1));
        if (!admin) return where + "expected an admin port 1..65535 after the control port";
        server.admin_port = *admin;
      }
    }
    for (const ServerEndpoint& other : out) {
      if (other.label() == server.label()) return where + "listed twice";
    }
    out.push_back(std::move(server));
    if (out.size() > kMaxServers) {
      return "at most " + std::to_string(kMaxServers) + " servers, got more";
    }
  }
  return out;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t start = 0; !text.empty() && start <= text.size();) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    out.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

bool is_loopback_v4(const std::string& address) {
  boost::system::error_code error;
  const auto parsed = boost::asio::ip::make_address_v4(address, error);
  return !error && parsed.is_loopback();
}

std::vector<std::string> source_addresses(int count) {
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) {
    out.push_back("127.0." + std::to_string(1 + i / 254) + "." + std::to_string(1 + i % 254));
  }
  return out;
}

std::optional<double> parse_duration_s(const std::string& text) {
  double value = 0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto [rest, error] = std::from_chars(begin, end, value);
  if (error != std::errc{} || rest == begin || !std::isfinite(value) || value < 0) {
    return std::nullopt;
  }
  const std::string unit(rest, end);
  if (unit.empty() || unit == "s") return value;
  if (unit == "ms") return value / 1000;
  if (unit == "m") return value * 60;
  return std::nullopt;
}

std::optional<std::vector<int>> parse_bot_counts(const std::string& text) {
  std::vector<int> counts;
  const char* at = text.data();
  const char* end = text.data() + text.size();
  while (at < end) {
    int value = 0;
    const auto [rest, error] = std::from_chars(at, end, value);
    if (error != std::errc{} || rest == at || value <= 0) return std::nullopt;
    if (!counts.empty() && value <= counts.back()) return std::nullopt;
    counts.push_back(value);
    at = rest;
    if (at < end) {
      if (*at != ',') return std::nullopt;
      ++at;
      if (at == end) return std::nullopt;
    }
  }
  if (counts.empty()) return std::nullopt;
  return counts;
}

std::vector<int> LoadTestConfig::steps() const {
  if (!sweep.empty()) return sweep;
  return {bots};
}

std::string LoadTestConfig::validate() const {
  if (servers.empty() || servers.size() > kMaxServers) {
    return "servers must be 1.." + std::to_string(kMaxServers) + ", got " +
           std::to_string(servers.size());
  }
  for (const ServerEndpoint& server : servers) {
    if (!is_ipv4(server.host)) {
      return "server must be a numeric IPv4 address, got \"" + server.host + "\"";
    }
    if (server.control_port == 0) return "control_port must be 1..65535, got 0";
  }
  if (!find_match.empty()) {
    const auto wanted = bot::parse_match_wanted(find_match);
    if (const auto* problem = std::get_if<std::string>(&wanted)) return *problem;
  }
  for (const int count : steps()) {
    if (count < 1 || count > 10000) return "bots must be 1..10000, got " + std::to_string(count);
  }
  if (match_size < 1 || match_size > 64) {
    return "match_size must be 1..64, got " + std::to_string(match_size);
  }
  if (!(duration_s >= 1 && duration_s <= 86400)) {
    return "duration must be 1 s..24 h, got " + number(duration_s) + " s";
  }
  if (!(ramp_per_s >= 0.1 && ramp_per_s <= 1000)) {
    return "ramp_per_s must be 0.1..1000 bots per second, got " + number(ramp_per_s);
  }
  if (!(settle_s >= 0 && settle_s <= 600)) {
    return "settle must be 0..600 s, got " + number(settle_s);
  }
  if (bots_per_address < 1 || bots_per_address > 16) {
    return "bots_per_address must be 1..16 (the server allows 16 control connections per "
           "address by default), got " +
           std::to_string(bots_per_address);
  }
  if (!(skill >= 0 && skill <= 1)) return "skill must be 0..1, got " + number(skill);
  if (!valid_prefix(name)) {
    return "name must be 1..12 characters of [A-Za-z0-9_.-] (bots are <name>s<step>-<k>), got \"" +
           name + "\"";
  }
  if (password.size() < 8 || password.size() > 1024) {
    return "password must be 8..1024 bytes, got " + std::to_string(password.size());
  }
  if (!(scrape_interval_s >= 0.2 && scrape_interval_s <= 60)) {
    return "scrape_interval must be 0.2..60 s, got " + number(scrape_interval_s);
  }
  if (server_pid < 0) return "server_pid must be >= 0, got " + std::to_string(server_pid);
  if (out.empty()) return "out must name a directory";
  return {};
}

}  // namespace ricochet::loadtest
