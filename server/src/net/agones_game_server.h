#pragma once
/// Where Agones says players reach this GameServer: the answer of the SDK sidecar's
/// `GET /gameserver` (sdkGameServer in Agones' sdks/swagger/sdk.swagger.json), of which the
/// directory row needs three fields:
///
///   {"object_meta":{...},"spec":{...},
///    "status":{"state":"Ready","address":"203.0.113.7",
///              "ports":[{"name":"control","port":7104},{"name":"game","port":7391}]}}
///
/// With the Fleet's Dynamic port policy each GameServer gets host ports of its own that Agones
/// maps to the container ports the server binds (7777, 7778), so the bound ports are not what
/// players connect to; status.address is the node's. The answer is untrusted input: anything
/// but that shape is refused with a reason (the caller logs it, counts it and keeps the
/// configured address).

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace ricochet::server {

/// The names of the Fleet's two ports (deploy/kubernetes/base/fleet.yaml, spec.ports[].name).
inline constexpr std::string_view kAgonesControlPortName = "control";  ///< TCP, the control channel
inline constexpr std::string_view kAgonesGamePortName = "game";        ///< UDP, the game channel

struct AgonesAddress {
  std::string host;                ///< status.address: an IP address or a DNS name
  std::uint16_t control_port = 0;  ///< status.ports[name = "control"].port, 1..65535
  std::uint16_t game_port = 0;     ///< status.ports[name = "game"].port, 1..65535
};

/// status.address and the ports named kAgonesControlPortName and kAgonesGamePortName, or what
/// is wrong with `json` as a sentence (not JSON, nested deeper than 32, no status, an address
/// that is empty or not a host name, a port missing, named twice, or not an integer 1..65535).
/// Other fields are ignored.
std::variant<AgonesAddress, std::string> parse_game_server(std::string_view json);

}  // namespace ricochet::server
