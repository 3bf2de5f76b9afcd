// libFuzzer target for the server's reader of the Agones SDK sidecar's `GET /gameserver` answer
// (server/src/net/agones_game_server.h), JSON the server takes from the network: any bytes.
// Nothing may crash; a parse is deterministic; an accepted answer has a host and both ports.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>

#include "agones_game_server.h"
#include "fuzz_check.h"

namespace {

using namespace ricochet::server;

using ricochet::fuzz::check;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view json(reinterpret_cast<const char*>(data), size);
  const auto first = parse_game_server(json);
  const auto second = parse_game_server(json);
  check(first.index() == second.index());
  if (const auto* error = std::get_if<std::string>(&first)) {
    check(!error->empty());
    check(*error == std::get<std::string>(second));
    return 0;
  }
  const AgonesAddress& address = std::get<AgonesAddress>(first);
  const AgonesAddress& again = std::get<AgonesAddress>(second);
  check(!address.host.empty());
  check(address.control_port != 0 && address.game_port != 0);
  check(address.host == again.host && address.control_port == again.control_port &&
        address.game_port == again.game_port);
  return 0;
}
