#include "ricochet/loadtest/fleet_directory.h"

#include <boost/asio/ip/address_v4.hpp>
#include <boost/json.hpp>
#include <unordered_set>

#include "ricochet/bot/server_trust.h"
#include "ricochet/tools/port_text.h"

namespace ricochet::loadtest {

namespace json = boost::json;

namespace {

/// Nesting deeper than the answer's own (object, array, object, array, object) is refused.
constexpr std::size_t kMaxDepth = 8;
constexpr std::size_t kMaxServerIdBytes = 64;

FleetError refuse(FleetRefusal reason, std::string message) {
  return FleetError{reason, std::move(message)};
}

bool is_ipv4(std::string_view text) {
  boost::system::error_code error;
  boost::asio::ip::make_address_v4(std::string(text), error);
  return !error;
}

/// An integer field of `row` in [min, max]; nullopt (and `problem` set) otherwise.
std::optional<std::int64_t> integer(const json::object& row, std::string_view key, std::int64_t min,
                                    std::int64_t max, std::string& problem) {
  const json::value* value = row.if_contains(key);
  if (value && value->is_int64() && value->get_int64() >= min && value->get_int64() <= max) {
    return value->get_int64();
  }
  problem = std::string(key) + " must be an integer " + std::to_string(min) + ".." +
            std::to_string(max) + ", got " +
            (value ? json::serialize(*value).substr(0, 40) : std::string("nothing"));
  return std::nullopt;
}

std::optional<std::string> text(const json::object& row, std::string_view key,
                                std::size_t max_bytes, std::string& problem) {
  const json::value* value = row.if_contains(key);
  if (value && value->is_string() && !value->get_string().empty() &&
      value->get_string().size() <= max_bytes) {
    return std::string(value->get_string());
  }
  problem = std::string(key) + " must be a string of 1.." + std::to_string(max_bytes) +
            " bytes, got " + (value ? json::serialize(*value).substr(0, 40) : "nothing");
  return std::nullopt;
}

/// One row into `server`; empty when usable, else the refusal.
std::optional<FleetError> read_row(const json::value& value, std::size_t index,
                                   ServerEndpoint& server, std::string& server_id, bool& self) {
  const std::string where = "servers[" + std::to_string(index) + "]";
  if (!value.is_object()) return refuse(FleetRefusal::BadServer, where + " is not an object");
  const json::object& row = value.get_object();
  std::string problem;
  const auto id = text(row, "server_id", kMaxServerIdBytes, problem);
  const auto host = id ? text(row, "host", 253, problem) : std::nullopt;
  const auto control = host ? integer(row, "control_port", 1, 65535, problem) : std::nullopt;
  std::optional<std::int64_t> admin;
  if (control) {
    const json::value* field = row.if_contains("admin_port");
    admin = field && field->is_null() ? 0 : integer(row, "admin_port", 1, 65535, problem);
  }
  const auto certificate = admin ? text(row, "certificate_sha256", 64, problem) : std::nullopt;
  std::optional<std::string> fingerprint;
  if (certificate) {
    fingerprint = bot::normalize_fingerprint(*certificate);
    if (!fingerprint || certificate->size() != 64) {
      problem = "certificate_sha256 must be 64 hex digits, got \"" + *certificate + "\"";
      fingerprint.reset();
    }
  }
  const json::value* self_field = row.if_contains("self");
  if (fingerprint && !(self_field && self_field->is_bool())) {
    problem = "self must be true or false";
    fingerprint.reset();
  }
  if (!fingerprint) return refuse(FleetRefusal::BadServer, where + ": " + problem);
  if (!is_ipv4(*host)) {
    return refuse(FleetRefusal::HostNotIpv4,
                  where + " (" + *id + "): host must be a numeric IPv4 address, got \"" +
                      host->substr(0, 64) + "\" (advertise_host of that server)");
  }
  server.host = *host;
  server.control_port = static_cast<std::uint16_t>(*control);
  server.admin_port = static_cast<std::uint16_t>(*admin);
  server.fingerprint = *fingerprint;
  server_id = *id;
  self = self_field->get_bool();
  return std::nullopt;
}

}  // namespace

const char* name(FleetRefusal reason) {
  switch (reason) {
    case FleetRefusal::NotJson:
      return "not_json";
    case FleetRefusal::NotAFleet:
      return "not_a_fleet";
    case FleetRefusal::BadServer:
      return "bad_server";
    case FleetRefusal::HostNotIpv4:
      return "host_not_ipv4";
    case FleetRefusal::Duplicate:
      return "duplicate";
    case FleetRefusal::NoServers:
      return "no_servers";
    case FleetRefusal::TooManyServers:
      return "too_many_servers";
  }
  return "unknown";
}

std::variant<std::vector<ServerEndpoint>, FleetError> parse_fleet(std::string_view body) {
  if (body.size() > kMaxFleetBytes) {
    return refuse(
        FleetRefusal::NotJson,
        "the answer is larger than the " + std::to_string(kMaxFleetBytes >> 20) + " MiB accepted");
  }
  json::parse_options options;
  options.max_depth = kMaxDepth;
  boost::system::error_code error;
  const json::value document = json::parse(body, error, {}, options);
  if (error) return refuse(FleetRefusal::NotJson, "not JSON: " + error.message());
  const json::value* servers =
      document.is_object() ? document.get_object().if_contains("servers") : nullptr;
  if (!servers || !servers->is_array()) {
    return refuse(FleetRefusal::NotAFleet, "expected an object with a \"servers\" array");
  }
  const json::array& rows = servers->get_array();
  if (rows.empty()) return refuse(FleetRefusal::NoServers, "the fleet directory lists no server");
  if (rows.size() > kMaxServers) {
    return refuse(FleetRefusal::TooManyServers, "at most " + std::to_string(kMaxServers) +
                                                    " servers, the directory lists " +
                                                    std::to_string(rows.size()));
  }
  std::vector<ServerEndpoint> out;
  std::unordered_set<std::string> ids;
  std::unordered_set<std::string> labels;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ServerEndpoint server;
    std::string id;
    bool self = false;
    if (auto refused = read_row(rows[i], i, server, id, self)) return std::move(*refused);
    if (!ids.insert(id).second || !labels.insert(server.label()).second) {
      return refuse(FleetRefusal::Duplicate, "servers[" + std::to_string(i) + "] (" + id + ", " +
                                                 server.label() + ") is listed twice");
    }
    out.insert(self ? out.begin() : out.end(), std::move(server));
  }
  return out;
}

std::variant<std::vector<ServerEndpoint>, FleetError> FleetReader::read(std::string_view body) {
  auto read = parse_fleet(body);
  if (const auto* error = std::get_if<FleetError>(&read)) {
    ++refused_[static_cast<std::size_t>(error->reason)];
  }
  return read;
}

std::variant<ServerEndpoint, std::string> parse_fleet_source(std::string_view text) {
  const std::size_t colon = text.find(':');
  ServerEndpoint server;
  server.host = std::string(text.substr(0, colon));
  if (!is_ipv4(server.host)) return "expected HOST:ADMIN_PORT with a numeric IPv4 HOST";
  const auto port =
      colon == std::string_view::npos ? std::nullopt : tools::parse_port(text.substr(colon + 1));
  if (!port) return "expected an admin port 1..65535 after the address";
  server.admin_port = *port;
  return server;
}

}  // namespace ricochet::loadtest
