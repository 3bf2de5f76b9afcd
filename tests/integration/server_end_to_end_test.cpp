// The server as ricochet-server runs it (Server: DB, matches, UDP, TLS, admin HTTP on their
// threads), driven over real loopback sockets: sign in over TLS, join, connect the game channel
// with the token, play, come back from a new address, and stop gracefully.
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "control_test_client.h"
#include "game_test_client.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"
#include "ricochet/wire/game.pb.h"
#include "server.h"

namespace ricochet::test {
namespace {

using namespace std::chrono_literals;
using server::test::ControlTestClient;

server::ServerConfig test_config(const std::filesystem::path& data_dir) {
  server::ServerConfig config;
  config.server.data_dir = data_dir.string();
  config.server.threads = 2;
  config.server.shutdown_grace_s = 5;
  config.control.bind = "127.0.0.1";
  config.control.port = 0;
  config.game.bind = "127.0.0.1";
  config.game.port = 0;
  config.admin.port = 0;
  config.matches.count = 2;
  config.matches.map = RICOCHET_SOURCE_DIR "/server/maps/arena.map";
  return config;
}

/// One player: a signed-in control connection and, once joined, a game connection.
struct Player {
  explicit Player(std::uint16_t control_port) : control(control_port) {}
  ControlTestClient control;
  wire::JoinMatchReply join;
  std::unique_ptr<GameTestClient> game;
  std::uint32_t sequence = 0;
  wire::ServerPayload newest;  ///< the newest ServerPayload received
  std::uint64_t payloads = 0;

  /// Joins `match` over TLS and connects the game channel from a fresh socket.
  void join_and_connect(std::uint32_t match, std::uint16_t game_port) {
    const wire::ServerMessage reply = control.request(ControlTestClient::join(match));
    ASSERT_TRUE(reply.has_join_match()) << reply.DebugString();
    join = reply.join_match();
    game = std::make_unique<GameTestClient>(join, game_port);
    ASSERT_TRUE(game->pump_until(proto::ConnectionState::Connected, 3s));
  }
  /// Sends one input per 1/60 s (running forward) and reads every payload, for `duration`.
  void play_for(std::chrono::milliseconds duration) {
    auto next_input = std::chrono::steady_clock::now();
    game->pump_for(duration, [this, &next_input] {
      if (std::chrono::steady_clock::now() >= next_input) {
        next_input += std::chrono::microseconds(16'667);
        wire::ClientPayload payload;
        wire::Input* input = payload.add_inputs();
        input->set_sequence(++sequence);
        input->set_move_forward(127);
        game->send(payload.SerializeAsString());
      }
      for (proto::ClientEvent& event : game->events()) {
        if (auto* bytes = std::get_if<proto::ClientUnreliable>(&event)) {
          wire::ServerPayload payload;
          ASSERT_TRUE(payload.ParseFromArray(bytes->bytes.data(), static_cast<int>(bytes->bytes.size())));
          if (payload.server_tick() >= newest.server_tick()) newest = payload;
          ++payloads;
        }
      }
      game->events().clear();
    });
  }
};

class ServerEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("ricochet-e2e-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    server_ = std::make_unique<server::Server>(test_config(dir_));
    server_->start();
  }
  void TearDown() override {
    server_.reset();
    std::filesystem::remove_all(dir_);
  }
  std::unique_ptr<Player> signed_in(const std::string& name) {
    auto player = std::make_unique<Player>(server_->control_port());
    EXPECT_TRUE(player->control.connect());
    EXPECT_EQ(player->control.peer_fingerprint(), server_->fingerprint());
    player->control.sign_in(name);
    return player;
  }

  std::filesystem::path dir_;
  std::unique_ptr<server::Server> server_;
};

TEST_F(ServerEndToEnd, TwoPlayersJoinPlayAndTheServerAppliesTheirInputs) {
  auto alice = signed_in("alice");
  auto bob = signed_in("bob");
  alice->join_and_connect(1, server_->game_port());
  bob->join_and_connect(1, server_->game_port());
  alice->play_for(700ms);
  bob->play_for(700ms);
  for (Player* player : {alice.get(), bob.get()}) {
    EXPECT_GT(player->payloads, 20u);
    EXPECT_NE(player->newest.your_entity_id(), 0u);
    EXPECT_GT(player->newest.last_input_sequence(), 0u);  // the server applied its inputs
    EXPECT_LE(player->newest.last_input_sequence(), player->sequence);
  }
  EXPECT_NE(alice->newest.your_entity_id(), bob->newest.your_entity_id());
  const wire::ServerMessage list = alice->control.request(ControlTestClient::list_matches());
  ASSERT_TRUE(list.has_list_matches());
  EXPECT_EQ(list.list_matches().matches(0).players(), 2);
}

TEST_F(ServerEndToEnd, APlayerComingBackFromANewAddressKeepsItsEntity) {
  auto alice = signed_in("alice");
  alice->join_and_connect(1, server_->game_port());
  alice->play_for(300ms);
  const std::uint32_t entity = alice->newest.your_entity_id();
  ASSERT_NE(entity, 0u);
  // The phone changed networks: the old socket goes quiet, a new one joins with a new token.
  auto old_game = std::move(alice->game);
  alice->sequence = 0;
  alice->newest = {};
  alice->join_and_connect(1, server_->game_port());
  alice->play_for(300ms);
  EXPECT_EQ(alice->newest.your_entity_id(), entity);
  // The replaced connection was told so.
  old_game->pump_for(300ms);
  EXPECT_EQ(old_game->transport().state(), proto::ConnectionState::Disconnected);
}

TEST_F(ServerEndToEnd, GracefulStopTellsThePlayersAndRecordsTheMatch) {
  auto alice = signed_in("alice");
  alice->join_and_connect(1, server_->game_port());
  alice->play_for(400ms);
  server_->stop();
  alice->game->pump_for(500ms);
  ASSERT_EQ(alice->game->transport().state(), proto::ConnectionState::Disconnected);
  EXPECT_EQ(alice->game->transport().disconnect_reason(), proto::DisconnectReason::ServerShutdown);
  EXPECT_EQ(server_->wait(), 0);
  server_.reset();

  auto store = db::open_sqlite_store({.path = (dir_ / "ricochet.db").string()});
  ASSERT_TRUE(store) << store.error().message;
  db::Matches matches(*store.value());
  const auto account = store.value()->find_account_by_key("alice");
  ASSERT_TRUE(account.ok() && account.value().has_value());
  const auto stats = matches.player_stats(account.value()->account.id);
  ASSERT_TRUE(stats) << stats.error().message;
  EXPECT_EQ(stats.value().matches, 1);
  EXPECT_GT(stats.value().seconds_played, 0.3);
}

}  // namespace
}  // namespace ricochet::test
