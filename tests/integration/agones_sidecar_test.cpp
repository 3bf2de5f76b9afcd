// The real ricochet-server binary under Agones, with AGONES_SDK_HTTP_PORT set, against a FAKE
// SDK sidecar (agones_sidecar_fake.h: the real one is a Go binary not available here) on
// 127.0.0.1, and ricochet_bot as the player. The contract, from Agones' sdk.swagger.json:
//
//   POST /ready {}           once, after the sockets are bound and the database is open
//   POST /health {}          every 2 s while every match ticks on time
//   PUT /metadata/label {"key":"map"|"mode"|"players"|"capacity","value":"..."}
//   POST /allocate {}        at the join of the first player a ticket placed here, or when
//                            the first player who joined directly is seated
//   POST /shutdown {}        when drained after SIGTERM, or after agones.shutdown_after_matches
//   GET /gameserver          once Ready, with placement on and an advertise key unset: the
//                            directory row advertises its status.address and status.ports
//
// Every wait is bounded and polls the fake's record; none waits for a deadline to pass.
#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>

#include "agones_sidecar_fake.h"
#include "control_test_client.h"
#include "ricochet/bot/fleet.h"
#include "run_until.h"
#include "server_process.h"

namespace ricochet::test::agones_sidecar_test {
namespace {

using namespace std::chrono_literals;
namespace asio = boost::asio;

constexpr int kShutdownGraceS = 5;
constexpr auto kStartBudget = 15s;
constexpr auto kExitBudget = std::chrono::seconds(kShutdownGraceS + 3);

/// The [matches] table: one free-for-all match on the arena for 16, waiting for `min_players`.
std::string matches_toml(int min_players, int time_limit_s = 600) {
  return "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
         "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\nrecord = "
         "false\nmin_players = " +
         std::to_string(min_players) + "\ntime_limit_s = " + std::to_string(time_limit_s) + "\n";
}

/// The server, started with AGONES_SDK_HTTP_PORT=`sdk_port` in its environment only.
std::unique_ptr<ServerProcess> start_server(const std::string& sdk_port, const std::string& matches,
                                            const std::string& more_toml = "") {
  setenv("AGONES_SDK_HTTP_PORT", sdk_port.c_str(), 1);
  auto server = std::make_unique<ServerProcess>(matches, kShutdownGraceS, more_toml);
  unsetenv("AGONES_SDK_HTTP_PORT");  // forked: the child has it
  return server;
}

/// Polls `done` every 20 ms for at most `limit`.
template <class Done>
bool eventually(Done done, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

bot::FleetConfig one_bot(const ServerProcess& server, const std::string& name) {
  bot::FleetConfig config;
  config.bot.host = "127.0.0.1";
  config.bot.control_port = server.control_port();
  config.bot.fingerprint = server.fingerprint();
  config.bot.name = name;
  config.bot.password = "password-of-" + name;
  config.bot.matches = 1;
  config.bots = 1;
  return config;
}

/// GET /metrics from the server's admin port.
std::string scrape(std::uint16_t admin_port) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  asio::io_context io;
  asio::ip::tcp::socket socket(io);
  socket.connect({asio::ip::address_v4::loopback(), admin_port});
  http::request<http::empty_body> request{http::verb::get, "/metrics", 11};
  request.set(http::field::host, "127.0.0.1");
  http::write(socket, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(socket, buffer, response);
  return response.body();
}

TEST(AgonesSidecar, ReadyAfterBindHealthLabelsAllocateOnAPlayerAndShutdownAfterTheDrain) {
  FakeAgonesSidecar sidecar;
  std::atomic<int> ready_before_ports_file{0};
  std::filesystem::path ports_file;
  sidecar.on_call([&](const FakeAgonesSidecar::Call& call) {
    if (call.path == "/ready" && !std::filesystem::exists(ports_file)) ++ready_before_ports_file;
  });
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(2));
  ports_file = server->dir() / "ports.json";
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();

  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/health") >= 3; }, 15s))
      << server->log();
  EXPECT_EQ(sidecar.count("POST", "/ready"), 1);
  EXPECT_EQ(ready_before_ports_file.load(), 0) << "POST /ready came before the sockets were bound";
  EXPECT_EQ(sidecar.state(), "Ready");
  // The pings are 2 s apart (a loaded machine may delay one, never hurry one).
  std::optional<std::chrono::steady_clock::time_point> previous;
  for (const auto& call : sidecar.calls()) {
    if (call.path != "/health") continue;
    if (previous) {
      EXPECT_GE(call.at - *previous, 1900ms);
    }
    previous = call.at;
  }
  ASSERT_TRUE(eventually([&] { return sidecar.labels().size() == 4; }, 5s));
  auto labels = sidecar.labels();
  EXPECT_EQ(labels["agones.dev/sdk-map"], "arena");
  EXPECT_EQ(labels["agones.dev/sdk-mode"], "ffa");
  EXPECT_EQ(labels["agones.dev/sdk-players"], "0");
  EXPECT_EQ(labels["agones.dev/sdk-capacity"], "16");
  EXPECT_EQ(sidecar.count("POST", "/allocate"), 0);

  // A player joins (the match waits for a second one): the server allocates itself.
  asio::io_context io;
  bot::Fleet fleet(io, one_bot(*server, "agones"));
  ASSERT_EQ(fleet.start(), "");
  ASSERT_TRUE(run_until(
      io, [&] { return sidecar.count("POST", "/allocate") == 1; }, 30s))
      << server->log();
  EXPECT_EQ(sidecar.state(), "Allocated");
  ASSERT_TRUE(run_until(
      io, [&] { return sidecar.labels()["agones.dev/sdk-players"] == "1"; }, 5s));

  const std::string metrics = scrape(server->admin_port());
  EXPECT_NE(metrics.find(R"(ricochet_agones_calls_total{call="ready",outcome="ok"} 1)"),
            std::string::npos)
      << metrics;

  server->terminate();
  std::optional<int> exit_code;
  ASSERT_TRUE(run_until(
      io, [&] { return (exit_code = server->wait_exit(0ms)).has_value(); }, kExitBudget));
  EXPECT_EQ(exit_code, std::optional<int>(0)) << server->log();
  const auto calls = sidecar.calls();
  ASSERT_FALSE(calls.empty());
  EXPECT_EQ(calls.back().path, "/shutdown");
  EXPECT_EQ(sidecar.count("POST", "/shutdown"), 1);
  EXPECT_EQ(sidecar.state(), "Shutdown");
  for (const auto& call : calls) EXPECT_EQ(call.status, 200u) << call.method << " " << call.path;
}

TEST(AgonesSidecar, APlacedPlayerAllocatesAtItsJoinADirectOneOnlyOnceSeated) {
  using server::test::ControlTestClient;
  FakeAgonesSidecar sidecar;
  // Placement on the server's own SQLite: a fleet of one, enough for a ticket.
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(2),
                             "[placement]\nenabled = \"on\"\nadvertise_host = \"127.0.0.1\"\n");
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();
  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/health") >= 1; }, 10s))
      << server->log();

  // A direct join with no game connection: the next ping goes (an allocation would go first)
  // and nothing is allocated.
  ControlTestClient direct(server->control_port());
  ASSERT_TRUE(direct.connect());
  direct.sign_in("direct");
  const wire::ServerMessage listed = direct.request(ControlTestClient::list_matches());
  ASSERT_EQ(listed.list_matches().matches_size(), 1) << listed.DebugString();
  const std::uint32_t match_id = listed.list_matches().matches(0).match_id();
  ASSERT_TRUE(direct.request(ControlTestClient::join(match_id)).has_join_match());
  const int pings = sidecar.count("POST", "/health");
  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/health") > pings + 1; }, 10s));
  EXPECT_EQ(sidecar.count("POST", "/allocate"), 0);
  EXPECT_EQ(sidecar.state(), "Ready");

  // A placed join allocates at once, though its player never connects over the game channel.
  ControlTestClient placed(server->control_port());
  ASSERT_TRUE(placed.connect());
  placed.sign_in("placed");
  wire::ClientMessage find;
  find.mutable_find_match()->set_mode("ffa");
  wire::ServerMessage found;
  ASSERT_TRUE(eventually(  // until the first heartbeat wrote the directory row
      [&] { return (found = placed.request(find)).has_find_match(); }, 10s))
      << found.DebugString();
  wire::ClientMessage join;
  join.mutable_join_match()->set_ticket(found.find_match().assignment().ticket());
  const wire::ServerMessage joined = placed.request(join);
  ASSERT_TRUE(joined.has_join_match()) << joined.DebugString();
  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/allocate") == 1; }, 5s))
      << server->log();
  EXPECT_EQ(sidecar.state(), "Allocated");
  EXPECT_EQ(sidecar.labels()["agones.dev/sdk-players"], "0");  // nobody seated yet
  server->terminate();
  EXPECT_EQ(server->wait_exit(kExitBudget), std::optional<int>(0)) << server->log();
}

/// find_match on `server` as a new account `name`, once its directory row is written.
wire::ServerMessage find_match_on(const ServerProcess& server, const std::string& name) {
  server::test::ControlTestClient client(server.control_port());
  EXPECT_TRUE(client.connect());
  client.sign_in(name);
  wire::ClientMessage find;
  find.mutable_find_match()->set_mode("ffa");
  wire::ServerMessage found;
  EXPECT_TRUE(eventually([&] { return (found = client.request(find)).has_find_match(); }, 10s))
      << found.DebugString();
  return found;
}

TEST(AgonesSidecar, TheDirectoryAdvertisesTheAddressAndPortsTheSidecarNames) {
  FakeAgonesSidecar sidecar;
  // Dynamic ports: the host ports players reach are not the container ports the server binds.
  sidecar.set_address("127.0.0.9", {{"control", 30777}, {"game", 30778}, {"admin", 30779}});
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(2),
                             "[placement]\nenabled = \"on\"\n");
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();
  const wire::ServerMessage found = find_match_on(*server, "advertised");
  ASSERT_TRUE(found.has_find_match()) << server->log();
  EXPECT_EQ(found.find_match().assignment().connection(), "127.0.0.9:30777");
  EXPECT_EQ(found.find_match().assignment().game_port(), 30778u);
  EXPECT_EQ(sidecar.count("GET", "/gameserver"), 1);
  server->terminate();
  EXPECT_EQ(server->wait_exit(kExitBudget), std::optional<int>(0)) << server->log();
}

TEST(AgonesSidecar, AGameServerAnswerThatIsNotOneKeepsTheConfiguredAddressLoggedAndCounted) {
  FakeAgonesSidecar sidecar;
  sidecar.answer_game_server(
      R"({"status":{"address":"127.0.0.9","ports":[{"name":"control","port":"30777"}]}})");
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(2),
                             "[placement]\nenabled = \"on\"\nadvertise_host = \"127.0.0.1\"\n");
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();
  const wire::ServerMessage found = find_match_on(*server, "configured");
  ASSERT_TRUE(found.has_find_match()) << server->log();
  EXPECT_EQ(found.find_match().assignment().connection(),
            "127.0.0.1:" + std::to_string(server->control_port()));
  EXPECT_EQ(found.find_match().assignment().game_port(), server->game_port());
  EXPECT_NE(server->log().find("placement: GET /gameserver's status.ports 'control' must have a "
                               "port 1..65535; advertising the configured address"),
            std::string::npos)
      << server->log();
  EXPECT_NE(scrape(server->admin_port()).find("ricochet_agones_gameserver_invalid_total 1"),
            std::string::npos);
  server->terminate();
  EXPECT_EQ(server->wait_exit(kExitBudget), std::optional<int>(0)) << server->log();
}

TEST(AgonesSidecar, ASidecarThatComesUpLateGetsReadyOnceItListens) {
  FakeAgonesSidecar sidecar(/*listening=*/false);
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(2));
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();
  ASSERT_TRUE(eventually(
      [&] {
        return server->log().find("to the SDK sidecar failed (io_error)") != std::string::npos;
      },
      10s))
      << server->log();
  EXPECT_TRUE(sidecar.calls().empty());
  sidecar.listen();
  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/health") >= 1; }, 10s))
      << server->log();
  EXPECT_EQ(sidecar.count("POST", "/ready"), 1);
  EXPECT_EQ(sidecar.state(), "Ready");
  EXPECT_NE(server->log().find("the SDK sidecar answers again"), std::string::npos);
  // The episode is logged once, not once per refused attempt.
  const std::string log = server->log();
  std::size_t warnings = 0;
  for (auto at = log.find("to the SDK sidecar failed"); at != std::string::npos;
       at = log.find("to the SDK sidecar failed", at + 1)) {
    ++warnings;
  }
  EXPECT_EQ(warnings, 1u) << log;
  server->terminate();
  EXPECT_EQ(server->wait_exit(kExitBudget), std::optional<int>(0)) << server->log();
  EXPECT_EQ(sidecar.count("POST", "/shutdown"), 1);
}

TEST(AgonesSidecar, ASidecarAnswering500IsRetriedAndCountedUntilItRecovers) {
  FakeAgonesSidecar sidecar;
  sidecar.fail(true);
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(2));
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();
  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/ready", 500) >= 3; }, 10s))
      << server->log();
  EXPECT_EQ(sidecar.state(), "Scheduled");
  EXPECT_NE(scrape(server->admin_port())
                .find(R"(ricochet_agones_calls_total{call="ready",outcome="http_5xx"})"),
            std::string::npos);
  EXPECT_NE(server->log().find("to the SDK sidecar failed (http_5xx)"), std::string::npos);
  sidecar.fail(false);
  ASSERT_TRUE(eventually([&] { return sidecar.count("POST", "/health") >= 1; }, 10s))
      << server->log();
  EXPECT_EQ(sidecar.count("POST", "/ready", 200), 1);
  EXPECT_EQ(sidecar.state(), "Ready");
  server->terminate();
  EXPECT_EQ(server->wait_exit(kExitBudget), std::optional<int>(0)) << server->log();
  EXPECT_EQ(sidecar.count("POST", "/shutdown"), 1);
}

TEST(AgonesSidecar, ShutdownAfterTheConfiguredNumberOfMatches) {
  FakeAgonesSidecar sidecar;
  auto server = start_server(std::to_string(sidecar.port()), matches_toml(1, 3),
                             "[agones]\nshutdown_after_matches = 1\n");
  ASSERT_TRUE(server->wait_listening(kStartBudget)) << server->log();
  asio::io_context io;
  bot::Fleet fleet(io, one_bot(*server, "onematch"));
  ASSERT_EQ(fleet.start(), "");
  // The bot plays the 3 s match to its end; then the server asks Agones to shut it down (which
  // would delete the pod: here the test sends the SIGTERM).
  ASSERT_TRUE(run_until(
      io, [&] { return sidecar.count("POST", "/shutdown") == 1; }, 40s))
      << server->log();
  EXPECT_EQ(sidecar.count("POST", "/allocate"), 1);
  EXPECT_EQ(sidecar.state(), "Shutdown");
  server->terminate();
  std::optional<int> exit_code;
  ASSERT_TRUE(run_until(
      io, [&] { return (exit_code = server->wait_exit(0ms)).has_value(); }, kExitBudget));
  EXPECT_EQ(exit_code, std::optional<int>(0)) << server->log();
  EXPECT_EQ(sidecar.count("POST", "/shutdown"), 1);  // not again after the drain
}

TEST(AgonesSidecar, AnInvalidPortIsAClearStartupError) {
  auto server = start_server("93x", matches_toml(2));
  EXPECT_EQ(server->wait_exit(kStartBudget), std::optional<int>(1));
  EXPECT_NE(server->log().find("AGONES_SDK_HTTP_PORT must be the Agones SDK sidecar's port "
                               "(1..65535), got \"93x\""),
            std::string::npos)
      << server->log();
}

}  // namespace
}  // namespace ricochet::test::agones_sidecar_test
