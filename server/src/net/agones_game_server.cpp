#include "agones_game_server.h"

// Boost.JSON compiled here, header-only (Debian ships no libboost_json for 1.81's headers).
#include <boost/json/src.hpp>
#include <optional>

namespace ricochet::server {
namespace json = boost::json;
namespace {

/// Longer than a DNS name may be (253) is not a host.
constexpr std::size_t kMaxHostLength = 253;

bool host_character(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '-' || c == ':';  // ':' for an IPv6 address
}

/// A JSON integer 1..65535, or nothing.
std::optional<std::uint16_t> port_of(const json::value& value) {
  std::int64_t port = 0;
  if (value.is_int64()) {
    port = value.get_int64();
  } else if (value.is_uint64() && value.get_uint64() <= 65535) {
    port = static_cast<std::int64_t>(value.get_uint64());
  } else {
    return std::nullopt;
  }
  if (port < 1 || port > 65535) return std::nullopt;
  return static_cast<std::uint16_t>(port);
}

}  // namespace

std::variant<AgonesAddress, std::string> parse_game_server(std::string_view text) {
  json::parse_options options;
  options.max_depth = 32;
  boost::system::error_code error;
  const json::value root =
      json::parse(json::string_view(text.data(), text.size()), error, json::storage_ptr(), options);
  if (error) return "GET /gameserver answered no JSON object: " + error.message();
  const json::object* object = root.if_object();
  const json::value* status_value = object ? object->if_contains("status") : nullptr;
  const json::object* status = status_value ? status_value->if_object() : nullptr;
  if (!status) return std::string("GET /gameserver answered no status object");

  AgonesAddress address;
  const json::value* host = status->if_contains("address");
  if (!host || !host->is_string() || host->get_string().empty() ||
      host->get_string().size() > kMaxHostLength) {
    return std::string(
        "GET /gameserver's status.address must be a host name or IP address of 1..253 "
        "characters (the GameServer may not be Scheduled yet)");
  }
  for (const char c : host->get_string()) {
    if (!host_character(c)) {
      return std::string("GET /gameserver's status.address has a character a host name has not");
    }
  }
  address.host = std::string(host->get_string());

  const json::value* ports_value = status->if_contains("ports");
  const json::array* ports = ports_value ? ports_value->if_array() : nullptr;
  if (!ports) return std::string("GET /gameserver's status.ports must be an array");
  for (const json::value& entry : *ports) {
    const json::object* port = entry.if_object();
    const json::value* name = port ? port->if_contains("name") : nullptr;
    if (!name || !name->is_string()) continue;  // a port of another name, or none: not ours
    std::uint16_t* slot = nullptr;
    if (name->get_string() == kAgonesControlPortName) slot = &address.control_port;
    if (name->get_string() == kAgonesGamePortName) slot = &address.game_port;
    if (!slot) continue;
    const std::string named(name->get_string());
    if (*slot != 0) return "GET /gameserver's status.ports names '" + named + "' twice";
    const json::value* number = port->if_contains("port");
    const auto value = number ? port_of(*number) : std::nullopt;
    if (!value) {
      return "GET /gameserver's status.ports '" + named + "' must have a port 1..65535";
    }
    *slot = *value;
  }
  for (const auto& [name, port] : {std::pair{kAgonesControlPortName, address.control_port},
                                   std::pair{kAgonesGamePortName, address.game_port}}) {
    if (port == 0) {
      return "GET /gameserver's status.ports has no port named '" + std::string(name) +
             "' (the Fleet's spec.ports must name the control and game ports so)";
    }
  }
  return address;
}

}  // namespace ricochet::server
