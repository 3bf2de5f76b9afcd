// parse_game_server: the address and ports of the SDK sidecar's GET /gameserver answer (the
// sdkGameServer of Agones' sdk.swagger.json), and every way an untrusted answer is refused.
#include "agones_game_server.h"

#include <gtest/gtest.h>

#include <string>
#include <variant>

namespace ricochet::server::agones_game_server_test {
namespace {

/// The refusal of `json`, or "parsed" when it was taken.
std::string refusal(const std::string& json) {
  const auto parsed = parse_game_server(json);
  if (const auto* why = std::get_if<std::string>(&parsed)) return *why;
  return "parsed";
}

/// A GameServer whose status has `address` and `ports` (JSON text of each).
std::string game_server(const std::string& address, const std::string& ports) {
  return R"({"object_meta":{"name":"ricochet-x7k2p","labels":{"agones.dev/fleet":"ricochet"}},)"
         R"("spec":{"ports":[]},"status":{"state":"Ready","address":)" +
         address + R"(,"ports":)" + ports + "}}";
}

TEST(AgonesGameServer, TakesTheAddressAndThePortsNamedControlAndGame) {
  const auto parsed = parse_game_server(game_server(
      R"("203.0.113.7")",
      R"([{"name":"admin","port":9},{"name":"game","port":7391},{"name":"control","port":7104}])"));
  ASSERT_TRUE(std::holds_alternative<AgonesAddress>(parsed)) << std::get<std::string>(parsed);
  const auto& address = std::get<AgonesAddress>(parsed);
  EXPECT_EQ(address.host, "203.0.113.7");
  EXPECT_EQ(address.control_port, 7104);
  EXPECT_EQ(address.game_port, 7391);
  EXPECT_EQ(refusal(game_server(R"("node-3.eu.example")",
                                R"([{"name":"control","port":1},{"name":"game","port":65535}])")),
            "parsed");
  EXPECT_EQ(refusal(game_server(R"("2001:db8::7")",
                                R"([{"name":"control","port":7104},{"name":"game","port":7391}])")),
            "parsed");
}

TEST(AgonesGameServer, RefusesWhatIsNotAGameServersAddressAndPorts) {
  const std::string ports = R"([{"name":"control","port":7104},{"name":"game","port":7391}])";
  const std::string deep = std::string(40, '[') + std::string(40, ']');
  for (const std::string& bad :
       {std::string(""), std::string("{"), std::string("null"), std::string("[]"),
        std::string(R"({"status":[]})"), deep, std::string(R"({"status":{"ports":[]}})")}) {
    EXPECT_NE(refusal(bad), "parsed") << bad;
  }
  EXPECT_NE(refusal(game_server(R"("")", ports)), "parsed");
  EXPECT_NE(refusal(game_server("7", ports)), "parsed");
  EXPECT_NE(refusal(game_server(R"("evil host\n")", ports)), "parsed");
  EXPECT_NE(refusal(game_server('"' + std::string(254, 'a') + '"', ports)), "parsed");
  EXPECT_EQ(refusal(game_server(R"("10.0.0.7")", R"({"control":7104})")),
            "GET /gameserver's status.ports must be an array");
  EXPECT_EQ(refusal(game_server(R"("10.0.0.7")", R"([{"name":"control","port":7104}])")),
            "GET /gameserver's status.ports has no port named 'game' (the Fleet's spec.ports must "
            "name the control and game ports so)");
  for (const std::string& port :
       {std::string("0"), std::string("65536"), std::string("-1"), std::string("7104.5"),
        std::string(R"("7104")"), std::string("null"), std::string("18446744073709551615")}) {
    EXPECT_EQ(refusal(game_server(R"("10.0.0.7")", R"([{"name":"control","port":)" + port +
                                                       R"(},{"name":"game","port":7391}])")),
              "GET /gameserver's status.ports 'control' must have a port 1..65535")
        << port;
  }
  EXPECT_EQ(
      refusal(game_server(R"("10.0.0.7")", R"([{"name":"game","port":7},)" + ports.substr(1))),
      "GET /gameserver's status.ports names 'game' twice");
}

}  // namespace
}  // namespace ricochet::server::agones_game_server_test
