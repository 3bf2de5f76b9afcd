#pragma once
/// `--fleet HOST:ADMIN`: the servers of a load test read from one server's GET /fleet (its admin
/// port; server/src/net/fleet_view.h has the JSON), each advertised row one ServerEndpoint as if
/// listed by --server, pinned to the certificate the row names. The answer is untrusted: every
/// field is checked, and a refusal names the reason (counted by FleetReader) and the field; it
/// never crashes. Rows without an admin port are kept with admin_port 0 (never scraped).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ricochet/loadtest/loadtest_config.h"

namespace ricochet::loadtest {

/// Why an answer of /fleet is refused.
enum class FleetRefusal : std::uint8_t {
  NotJson,         ///< not parsable JSON, or deeper or longer than accepted
  NotAFleet,       ///< not an object with a "servers" array
  BadServer,       ///< a row's field missing, of the wrong type or out of range
  HostNotIpv4,     ///< a row's host is not a numeric IPv4 address (all the load test reaches)
  Duplicate,       ///< two rows with one server id or one host:control port
  NoServers,       ///< no row at all
  TooManyServers,  ///< more rows than kMaxServers
};
inline constexpr std::size_t kFleetRefusalCount =
    static_cast<std::size_t>(FleetRefusal::TooManyServers) + 1;
/// "not_json", "not_a_fleet", "bad_server", "host_not_ipv4", "duplicate", "no_servers",
/// "too_many_servers".
const char* name(FleetRefusal reason);

struct FleetError {
  FleetRefusal reason = FleetRefusal::NotJson;
  std::string message;  ///< what was expected and what came, naming the row and field
};

/// The largest /fleet answer read, bytes (64 servers with 4096 matches each stay below it).
inline constexpr std::size_t kMaxFleetBytes = 32u << 20;

/// The servers of the answer `body`, the answering server's own row ("self") first, then the
/// others in the answer's order.
std::variant<std::vector<ServerEndpoint>, FleetError> parse_fleet(std::string_view body);

/// parse_fleet with a count of refusals by reason.
class FleetReader {
 public:
  std::variant<std::vector<ServerEndpoint>, FleetError> read(std::string_view body);
  std::uint64_t refused(FleetRefusal reason) const {
    return refused_[static_cast<std::size_t>(reason)];
  }

 private:
  std::array<std::uint64_t, kFleetRefusalCount> refused_{};
};

/// "HOST:ADMIN_PORT" (numeric IPv4, port 1..65535) → the server asked for /fleet, with only
/// host and admin_port set; or why not.
std::variant<ServerEndpoint, std::string> parse_fleet_source(std::string_view text);

}  // namespace ricochet::loadtest
