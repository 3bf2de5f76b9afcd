// libFuzzer target for `ricochet-loadtest --fleet`'s reader of a server's GET /fleet answer
// (tools/loadtest/include/ricochet/loadtest/fleet_directory.h): bytes from the network,
// untrusted. Nothing may crash; a read is deterministic; a refusal is counted once under its
// reason; an accepted fleet is 1..kMaxServers servers, each a numeric IPv4 host with a control
// port, a pinned certificate and no two alike.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>
#include <variant>

#include "fuzz_check.h"
#include "ricochet/loadtest/fleet_directory.h"

namespace {

using namespace ricochet::loadtest;

using ricochet::fuzz::check;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  FleetReader reader;
  const auto first = reader.read(text);
  const auto second = parse_fleet(text);
  check(first.index() == second.index());
  if (const auto* error = std::get_if<FleetError>(&first)) {
    check(error->reason == std::get<FleetError>(second).reason);
    check(error->message == std::get<FleetError>(second).message && !error->message.empty());
    for (std::size_t i = 0; i < kFleetRefusalCount; ++i) {
      const auto reason = static_cast<FleetRefusal>(i);
      check(reader.refused(reason) == (reason == error->reason ? 1u : 0u));
    }
    return 0;
  }
  const auto& servers = std::get<std::vector<ServerEndpoint>>(first);
  check(!servers.empty() && servers.size() <= kMaxServers);
  check(servers.size() == std::get<std::vector<ServerEndpoint>>(second).size());
  std::set<std::string> labels;
  for (const ServerEndpoint& server : servers) {
    check(server.control_port != 0 && !server.fingerprint.empty() && !server.host.empty());
    check(labels.insert(server.label()).second);
  }
  return 0;
}
