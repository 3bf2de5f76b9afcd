// The server as ricochet-server runs it (Server: DB, matches, UDP, TLS, admin HTTP on their
// threads), driven over real loopback sockets: sign in over TLS, join, connect the game channel
// with the token, play, come back from a new address, survive a chat flood, and stop gracefully.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include "admin_get.h"
#include "control_test_client.h"
#include "game_test_client.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/rating.h"
#include "ricochet/db/store.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/match_replay.h"
#include "ricochet/wire/game.pb.h"
#include "server.h"
#include "temp_dir.h"

namespace ricochet::test::server_end_to_end_test {
namespace {

using namespace std::chrono_literals;
using server::test::ControlTestClient;

server::ServerConfig test_config(const std::filesystem::path& data_dir) {
  server::ServerConfig config;
  config.server.data_dir = data_dir.string();
  config.server.threads = 2;
  config.server.shutdown_grace_s = 5;
  // Hashes at the priority of the other test processes the cores are shared with (the lower
  // priority itself: db_tests, DbWorker.PasswordThreadsRunAtTheirLowerPriority).
  config.db.password_thread_nice = 0;
  config.control.bind = "127.0.0.1";
  config.control.port = 0;
  config.game.bind = "127.0.0.1";
  config.game.port = 0;
  config.admin.port = 0;
  config.matches.count = 2;
  config.matches.maps = {RICOCHET_SOURCE_DIR "/server/maps/arena.toml"};
  // One player starts the match at once, so whoever plays is in its record.
  config.matches.min_players = 1;
  config.matches.warmup_s = 0;
  return config;
}

/// A player's totals in the database at `db_path` once the server has stopped; nothing, and a
/// test failure naming why, when they cannot be read.
std::optional<db::PlayerStats> stats_of(const std::string& db_path, const std::string& username) {
  auto store = db::open_sqlite_store({.path = db_path});
  if (!store) {
    ADD_FAILURE() << store.error().message;
    return std::nullopt;
  }
  const auto account = store.value()->find_account_by_key(username);
  if (!account.ok() || !account.value().has_value()) {
    ADD_FAILURE() << "no account " << username;
    return std::nullopt;
  }
  db::Matches matches(*store.value());
  auto stats = matches.player_stats(account.value()->account.id);
  if (!stats) {
    ADD_FAILURE() << stats.error().message;
    return std::nullopt;
  }
  return stats.value();
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
  std::unique_ptr<proto::SnapshotDecoder> decoder;  ///< from the join reply's quantisation
  std::vector<proto::EntityState> view;             ///< the newest decoded snapshot
  std::optional<proto::EntityState> first_self;     ///< own entity in the first decoded snapshot
  std::uint32_t buttons = 0;                        ///< held in every input (bit 1: fire)
  std::vector<wire::GameEvent> game_events;         ///< every reliable GameEvent received

  std::optional<proto::EntityState> self() const {
    for (const proto::EntityState& entity : view) {
      if (entity.id == newest.your_entity_id()) return entity;
    }
    return std::nullopt;
  }

  /// Joins `match` over TLS and connects the game channel from a fresh socket.
  void join_and_connect(std::uint32_t match, std::uint16_t game_port) {
    const wire::ServerMessage reply = control.request(ControlTestClient::join(match));
    ASSERT_TRUE(reply.has_join_match()) << reply.DebugString();
    join = reply.join_match();
    std::string error;
    const auto spec = proto::from_wire(join.quantization(), error);
    ASSERT_TRUE(spec) << error;
    EXPECT_EQ(join.tick_rate_hz(), 60u);
    decoder = std::make_unique<proto::SnapshotDecoder>(*spec);
    spec_ = *spec;
    game = std::make_unique<GameTestClient>(join, game_port);
    ASSERT_TRUE(game->pump_until(proto::ConnectionState::Connected, 3s));
  }
  /// Sends one input per 1/60 s (running forward) and reads every payload, for `duration`.
  proto::QuantizationSpec spec_;

  void play_for(std::chrono::milliseconds duration) {
    auto next_input = std::chrono::steady_clock::now();
    game->pump_for(duration, [this, &next_input] {
      if (std::chrono::steady_clock::now() >= next_input) {
        next_input += std::chrono::microseconds(16'667);
        wire::ClientPayload payload;
        wire::Input* input = payload.add_inputs();
        input->set_sequence(++sequence);
        input->set_move_forward(127);
        input->set_buttons(buttons);
        payload.set_ack_snapshot_tick(decoder->has_snapshot() ? decoder->newest_tick() : 0);
        game->send(payload.SerializeAsString());
      }
      for (proto::ClientEvent& event : game->events()) {
        if (auto* reliable = std::get_if<proto::ClientReliable>(&event)) {
          wire::GameEvent game_event;
          ASSERT_TRUE(game_event.ParseFromArray(reliable->bytes.data(),
                                                static_cast<int>(reliable->bytes.size())));
          game_events.push_back(std::move(game_event));
        }
        if (auto* bytes = std::get_if<proto::ClientUnreliable>(&event)) {
          wire::ServerPayload payload;
          ASSERT_TRUE(
              payload.ParseFromArray(bytes->bytes.data(), static_cast<int>(bytes->bytes.size())));
          if (payload.server_tick() >= newest.server_tick()) newest = payload;
          ++payloads;
          const proto::SnapshotDecodeResult decoded = decoder->decode(payload.snapshot());
          if (!decoded.ok) continue;  // older than one already decoded
          view.clear();
          for (const proto::QuantizedEntity& entity : decoded.entities) {
            view.push_back(proto::dequantize(entity, spec_));
          }
          if (!first_self) first_self = self();
        }
      }
      game->events().clear();
    });
  }
};

class ServerEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = std::make_unique<server::Server>(test_config(dir_.path()));
    server_->start();
  }
  void TearDown() override { server_.reset(); }
  std::unique_ptr<Player> signed_in(const std::string& name) {
    auto player = std::make_unique<Player>(server_->control_port());
    EXPECT_TRUE(player->control.connect());
    EXPECT_EQ(player->control.peer_fingerprint(), server_->fingerprint());
    player->control.sign_in(name);
    return player;
  }

  TempDir dir_{"ricochet-e2e"};  ///< outlives the server (declared first)
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
  for (Player* player : {alice.get(), bob.get()}) {
    EXPECT_EQ(player->view.size(), 2u);  // each sees both
    ASSERT_TRUE(player->first_self && player->self());
    double moved = 0;
    for (int axis : {0, 2}) {
      const double d = player->self()->position_m[axis] - player->first_self->position_m[axis];
      moved += d * d;
    }
    // Running forward at up to 7 m/s for most of 1.4 s (each player's inputs stop while the
    // other plays): well over a metre.
    EXPECT_GT(std::sqrt(moved), 1.0);
  }
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
  // Told after the match record is committed; a slow disk may take a while.
  ASSERT_TRUE(alice->game->pump_until(proto::ConnectionState::Disconnected, 5s));
  EXPECT_EQ(alice->game->transport().disconnect_reason(), proto::DisconnectReason::ServerShutdown);
  bool told_match_ended = false;
  for (const proto::ClientEvent& event : alice->game->events()) {
    if (const auto* reliable = std::get_if<proto::ClientReliable>(&event)) {
      wire::GameEvent game_event;
      ASSERT_TRUE(game_event.ParseFromArray(reliable->bytes.data(),
                                            static_cast<int>(reliable->bytes.size())));
      told_match_ended |= game_event.has_match_ended();
    }
  }
  EXPECT_TRUE(told_match_ended);
  // The results come over the control channel, then SHUTTING_DOWN.
  const auto results = alice->control.receive(3s);
  ASSERT_TRUE(results && results->has_match_results())
      << (results ? results->DebugString() : "nothing");
  const wire::MatchResults& match = results->match_results();
  ASSERT_EQ(match.players_size(), 1);
  EXPECT_EQ(match.mode(), "ffa");
  EXPECT_TRUE(match.aborted());  // stopped by the server: no winner, no rating change
  EXPECT_EQ(match.end_reason(), wire::MATCH_END_REASON_SERVER_SHUTDOWN);
  EXPECT_EQ(match.team_scores_size(), 0);
  const wire::PlayerMatchResult& player = match.players(0);
  EXPECT_EQ(player.username(), "alice");
  EXPECT_EQ(player.team(), wire::TEAM_NONE);
  EXPECT_FALSE(player.won());
  EXPECT_EQ(player.rating_before(), db::kInitialRating);
  EXPECT_EQ(player.rating_after(), db::kInitialRating);
  EXPECT_EQ(player.rank(), 1u);  // the only player on the board
  EXPECT_GT(player.seconds_played(), 0.3);
  EXPECT_EQ(server_->wait(), 0);
  server_.reset();

  const std::optional<db::PlayerStats> stats = stats_of(dir_.file("ricochet.db"), "alice");
  ASSERT_TRUE(stats);
  EXPECT_EQ(stats->matches, 1);  // an aborted match counts in the totals
  EXPECT_EQ(stats->wins, 0);
  EXPECT_GT(stats->seconds_played, 0.3);
  // Alice's match is recorded; the second match, which nobody joined, leaves no file.
  std::vector<std::string> recordings;
  for (const auto& entry : std::filesystem::directory_iterator(dir_.path() / "recordings")) {
    recordings.push_back(entry.path().filename().string());
  }
  ASSERT_EQ(recordings.size(), 1u);
  EXPECT_EQ(recordings[0].rfind("match-1-", 0), 0u) << recordings[0];
}

TEST(ServerStop, APlayerStillWaitingForOpponentsIsToldTheMatchEndedAndGetsItsResults) {
  TempDir dir{"ricochet-e2e-waiting"};
  server::ServerConfig config = test_config(dir.path());
  config.matches.min_players = 2;  // alice alone: the match waits for an opponent
  auto server = std::make_unique<server::Server>(config);
  server->start();
  auto alice = std::make_unique<Player>(server->control_port());
  ASSERT_TRUE(alice->control.connect());
  alice->control.sign_in("alice");
  alice->join_and_connect(1, server->game_port());
  alice->play_for(300ms);
  server->stop();
  ASSERT_TRUE(alice->game->pump_until(proto::ConnectionState::Disconnected, 5s));
  EXPECT_EQ(alice->game->transport().disconnect_reason(), proto::DisconnectReason::ServerShutdown);
  // Results to every player of the match, one who never played included: the match is over.
  const auto results = alice->control.receive(3s);
  ASSERT_TRUE(results && results->has_match_results())
      << (results ? results->DebugString() : "nothing");
  const wire::MatchResults& match = results->match_results();
  EXPECT_EQ(match.match_id(), 1u);
  EXPECT_EQ(match.mode(), "ffa");
  EXPECT_TRUE(match.aborted());
  EXPECT_EQ(match.end_reason(), wire::MATCH_END_REASON_SERVER_SHUTDOWN);
  EXPECT_EQ(match.players_size(), 0);  // nobody played a running tick: nothing is recorded
  EXPECT_EQ(server->wait(), 0);
  server.reset();
  const std::optional<db::PlayerStats> stats = stats_of(dir.file("ricochet.db"), "alice");
  ASSERT_TRUE(stats);
  EXPECT_EQ(stats->matches, 0);
}

TEST_F(ServerEndToEnd, LeavingTheMatchClosesTheGameConnectionWithTheReasonLeft) {
  auto alice = signed_in("alice");
  alice->join_and_connect(1, server_->game_port());
  alice->play_for(200ms);
  EXPECT_TRUE(alice->control.request(ControlTestClient::leave()).has_leave_match());
  ASSERT_TRUE(alice->game->pump_until(proto::ConnectionState::Disconnected, 2s));
  EXPECT_EQ(alice->game->transport().disconnect_reason(), proto::DisconnectReason::Left);
}

/// The value of one series in a Prometheus text page (-1 when absent).
double metric(const std::string& page, const std::string& series) {
  const auto at = page.find("\n" + series + " ");
  if (at == std::string::npos) return -1;
  return std::stod(page.substr(at + series.size() + 2));
}

TEST_F(ServerEndToEnd, HostileTrafficIsDroppedCountedAndDisturbsNoOne) {
  auto alice = signed_in("alice");
  alice->join_and_connect(1, server_->game_port());
  alice->play_for(300ms);
  const std::uint64_t before = alice->payloads;

  // Mallory: garbage, an oversized datagram, truncated packets, a request with a forged token,
  // and alice's own token replayed from another address, while alice plays.
  GameTestClient mallory(alice->join, server_->game_port());  // alice's token, another socket
  mallory.pump_for(200ms);  // its connection requests, before the flood rate-limits its address
  std::mt19937 random(1);
  std::vector<std::uint8_t> garbage(1200);
  for (int i = 0; i < 400; ++i) {
    for (auto& byte : garbage) byte = static_cast<std::uint8_t>(random());
    mallory.send_raw(garbage);                                // forged MAC / malformed
    mallory.send_raw(std::vector<std::uint8_t>(1500, 0x55));  // oversized
    mallory.send_raw({0x00, 0x01});                           // truncated
    // Paced, so that the kernel's receive buffer does not drop them before the server sees them.
    if (i % 5 == 4) std::this_thread::sleep_for(2ms);
  }
  alice->play_for(600ms);
  mallory.pump_for(300ms);
  EXPECT_NE(mallory.transport().state(), proto::ConnectionState::Connected);
  // Alice kept getting her snapshots at the full rate (60 Hz; 600 ms is about 36).
  EXPECT_GT(alice->payloads - before, 25u);

  const std::string page = ricochet::test::admin_get(server_->admin_port(), "/metrics");
  EXPECT_GT(metric(page, R"(ricochet_game_dropped_total{reason="oversized"})"), 0) << page;
  EXPECT_GT(metric(page, R"(ricochet_game_dropped_total{reason="token_reused"})"), 0);
  // None of the flood is shaped like a request, so the server remembers nothing of mallory's
  // address for it (PROTOCOL.md Game channel transport §12): each datagram is counted by what
  // it is.
  EXPECT_GT(metric(page, R"(ricochet_game_dropped_total{reason="truncated"})"), 0);
  // Each of the 1200 datagrams that reached the server is counted under some reason; a loaded
  // machine's kernel may drop a few before the server sees them.
  double dropped = 0;
  std::istringstream lines(page);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("ricochet_game_dropped_total{", 0) == 0)
      dropped += std::stod(line.substr(line.rfind(' ') + 1));
  }
  EXPECT_GE(dropped, 900);
  EXPECT_LE(dropped, 1200 + 10);  // mallory's own handshake packets at most
  EXPECT_EQ(metric(page, R"(ricochet_game_connections{state="connected"})"), 1);
  EXPECT_EQ(metric(page, R"(ricochet_match_players{match="1",state="connected"})"), 1);
  EXPECT_EQ(metric(page, "ricochet_players"), 1);
  EXPECT_EQ(metric(page, "ricochet_matches"), 2);
  // What a soak run watches for leaks: this process's memory and descriptors, the database's size.
  EXPECT_GT(metric(page, "process_resident_memory_bytes"), 1 << 20);
  EXPECT_GT(metric(page, "process_open_fds"), 3);
  EXPECT_GT(metric(page, "ricochet_db_file_bytes"), 4096);
  for (const char* phase : {"rules", "combat", "physics", "total"}) {
    EXPECT_NE(page.find(std::string("ricochet_tick_phase_seconds_count{match=\"1\",phase=\"") +
                        phase + "\"}"),
              std::string::npos)
        << phase;
  }
  EXPECT_EQ(ricochet::test::admin_get(server_->admin_port(), "/healthz").substr(0, 2), "ok");
}

/// Three players in match 1, and Mallory: one account signed in on eight TLS sessions, all in
/// match 1, the first also playing. flood() sends each session's whole request burst of chat
/// lines at once (320 lines of 156 bytes; `playing_lines` of them from the session that plays,
/// for a server whose request limits were lifted) while everyone plays, and reports what the
/// players saw.
class ChatFlood : public ServerEndToEnd {
 protected:
  static constexpr int kSessions = 8;
  static constexpr int kLinesPerSession = 40;  // one session's whole request burst
  static constexpr int kLines = kSessions * kLinesPerSession;

  struct Outcome {
    int accepted = 0;      ///< chat replies
    int rate_limited = 0;  ///< RATE_LIMITED replies
    int not_in_match = 0;  ///< NOT_IN_MATCH replies (the sessions that do not play the account)
    int victims_connected = 0;
    double worst_snapshot_share = 1;  ///< snapshots received / ticks, the worst victim's
    std::vector<long> lines_seen;     ///< chat events received, by victim, then Mallory's
  };

  void SetUp() override {}  // each test starts the server with its config
  void start(server::ServerConfig config) {
    server_ = std::make_unique<server::Server>(std::move(config));
    server_->start();
  }

  Outcome flood(int playing_lines = kLinesPerSession) {
    Outcome outcome;
    const auto lines_of = [playing_lines](std::size_t session) {
      return session == 0 ? playing_lines : kLinesPerSession;
    };
    // Everyone signs in first (password hashing takes a while), then joins.
    std::vector<std::unique_ptr<Player>> victims;
    for (const char* name : {"bob", "carol", "dave"}) victims.push_back(signed_in(name));
    std::vector<std::unique_ptr<Player>> mallory;
    for (int session = 0; session < kSessions; ++session) {
      auto player = std::make_unique<Player>(server_->control_port());
      EXPECT_TRUE(player->control.connect());
      player->control.sign_in("mallory", session == 0);
      mallory.push_back(std::move(player));
    }
    for (auto& victim : victims) victim->join_and_connect(1, server_->game_port());
    // One session plays an account, the one that joined last: mallory's first, whose game
    // connection is up. The others joined before it and still chat as the account.
    for (int session = 1; session < kSessions; ++session) {
      EXPECT_TRUE(mallory[session]->control.request(ControlTestClient::join(1)).has_join_match());
    }
    mallory[0]->join_and_connect(1, server_->game_port());
    // Every player's socket is served in turn, a few milliseconds each, like players on their
    // own machines (datagrams wait in the kernel meanwhile).
    const auto play_all = [&](std::chrono::milliseconds duration) {
      const auto until = std::chrono::steady_clock::now() + duration;
      while (std::chrono::steady_clock::now() < until) {
        for (auto& victim : victims) victim->play_for(4ms);
        mallory[0]->play_for(1ms);
      }
    };
    play_all(300ms);
    struct Seen {
      std::uint64_t payloads = 0;
      std::uint32_t tick = 0;
    };
    std::vector<Seen> before;
    for (auto& victim : victims) before.push_back({victim->payloads, victim->newest.server_tick()});

    for (std::size_t session = 0; session < mallory.size(); ++session) {
      std::vector<std::uint8_t> frames;
      for (int line = 0; line < lines_of(session); ++line) {
        wire::ClientMessage chat = ControlTestClient::chat("flood " + std::string(150, 'x'));
        chat.set_request_id(static_cast<std::uint32_t>(1000 + line));
        EXPECT_TRUE(proto::append_frame(chat, frames));
      }
      mallory[session]->control.send_bytes(frames);
    }
    play_all(1500ms);
    for (std::size_t session = 0; session < mallory.size(); ++session) {
      for (int line = 0; line < lines_of(session); ++line) {
        const auto reply = mallory[session]->control.receive(2s);
        if (!reply) break;
        if (reply->has_chat()) ++outcome.accepted;
        if (reply->has_error() && reply->error().code() == wire::RATE_LIMITED) {
          ++outcome.rate_limited;
        }
        if (reply->has_error() && reply->error().code() == wire::NOT_IN_MATCH) {
          ++outcome.not_in_match;
        }
      }
    }
    play_all(1000ms);  // the last accepted lines reach everyone

    for (std::size_t i = 0; i < victims.size(); ++i) {
      Player& victim = *victims[i];
      const bool up = victim.game->transport().state() == proto::ConnectionState::Connected;
      outcome.victims_connected += up ? 1 : 0;
      const auto reason = victim.game->transport().disconnect_reason();
      EXPECT_TRUE(up) << "victim " << i
                      << " disconnected: " << (reason ? proto::name(*reason) : "not connected");
      // One snapshot per tick (60 Hz each): the share of the ticks since the flood that came.
      const double ticks = victim.newest.server_tick() - before[i].tick;
      const double share = ticks > 0 ? (victim.payloads - before[i].payloads) / ticks : 0;
      outcome.worst_snapshot_share = std::min(outcome.worst_snapshot_share, share);
      EXPECT_GE(share, 0.95) << "victim " << i << ": " << victim.payloads - before[i].payloads
                             << " snapshots over " << ticks << " ticks";
    }
    victims.push_back(std::move(mallory[0]));
    for (const auto& player : victims) {
      outcome.lines_seen.push_back(
          std::count_if(player->game_events.begin(), player->game_events.end(),
                        [](const wire::GameEvent& event) { return event.has_chat(); }));
    }
    std::printf(
        "chat flood: %d of 3 victims connected, worst snapshot share %.3f, %d lines accepted, "
        "%d RATE_LIMITED, %d NOT_IN_MATCH\n",
        outcome.victims_connected, outcome.worst_snapshot_share, outcome.accepted,
        outcome.rate_limited, outcome.not_in_match);
    return outcome;
  }
};

TEST_F(ChatFlood, FromOneAccountOnManySessionsIsRefusedAndDisconnectsNoOne) {
  start(test_config(dir_.path()));  // the default chat limits
  const Outcome outcome = flood();
  EXPECT_EQ(outcome.victims_connected, 3);
  // Only the session that plays the account chats as it (issue 29: the seven it replaced did);
  // of its burst, the account's limit lets a few pass.
  EXPECT_EQ(outcome.not_in_match, kLines - kLinesPerSession);
  EXPECT_LE(outcome.accepted, 10);
  EXPECT_EQ(outcome.accepted + outcome.rate_limited, kLinesPerSession);
  for (const long lines : outcome.lines_seen) EXPECT_EQ(lines, outcome.accepted);
  const std::string page = ricochet::test::admin_get(server_->admin_port(), "/metrics");
  EXPECT_GE(metric(page, R"(ricochet_chat_refused_total{limit="account"})"), kLinesPerSession - 10)
      << page;
  EXPECT_EQ(metric(page, R"(ricochet_game_disconnects_total{reason="reliable_overflow"})"), 0);
}

TEST_F(ChatFlood, ThatPassesTheRateLimitsIsDroppedForPlayersBehindNeverDisconnectingThem) {
  // An operator who lifted the chat limits: every line is accepted and broadcast at once, more
  // than the players can ack in time. Each player misses lines, never its connection.
  server::ServerConfig config = test_config(dir_.path());
  config.control.chat_account_lines_per_s = 100;
  config.control.chat_account_burst = 1000;
  config.control.chat_match_lines_per_s = 1000;
  config.control.chat_match_burst = 1000;
  config.control.messages_per_second = 1000;  // and the requests per connection
  config.control.message_burst = 1000;
  start(config);
  const Outcome outcome = flood(kLines);  // all from the session that plays
  EXPECT_EQ(outcome.victims_connected, 3);
  EXPECT_EQ(outcome.accepted, kLines);
  EXPECT_EQ(outcome.not_in_match, kLines - kLinesPerSession);
  const std::string page = ricochet::test::admin_get(server_->admin_port(), "/metrics");
  const double dropped = metric(page, "ricochet_game_reliable_dropped_total");
  EXPECT_GT(dropped, 0) << page;
  // Every line accepted went to each of the four players: received or dropped, none lost.
  double seen = 0;
  for (const long lines : outcome.lines_seen) seen += static_cast<double>(lines);
  EXPECT_EQ(seen + dropped, 4.0 * kLines);
  std::printf("chat flood without limits: %.0f chat events received, %.0f dropped\n", seen,
              dropped);
  EXPECT_EQ(metric(page, R"(ricochet_game_disconnects_total{reason="reliable_overflow"})"), 0);
}

/// An admin HTTP response: its status and body.
struct HttpResponse {
  int status = 0;
  std::string body;
};

/// `method` `path` on the admin port, with "Authorization: Bearer `token`" unless it is empty.
HttpResponse http_request(std::uint16_t port, const std::string& method, const std::string& path,
                          const std::string& token = "") {
  const std::string response = ricochet::test::admin_response(port, path, method, token);
  HttpResponse out;
  if (response.rfind("HTTP/1.1 ", 0) == 0) out.status = std::stoi(response.substr(9, 3));
  out.body = ricochet::test::body_of(response);
  return out;
}

/// Issue 29: an operator bans an account while it plays. Three players and Mallory in match 1,
/// Mallory signed in on two control connections (one plays).
class AccountBan : public ServerEndToEnd {
 protected:
  struct Seen {
    std::uint64_t payloads = 0;
    std::uint32_t tick = 0;
  };

  void SetUp() override {
    ServerEndToEnd::SetUp();
    for (const char* name : {"bob", "carol", "dave"}) victims_.push_back(signed_in(name));
    mallory_ = std::make_unique<Player>(server_->control_port());
    EXPECT_TRUE(mallory_->control.connect());
    mallory_token_ = mallory_->control.sign_in("mallory").session_token();
    idle_ = std::make_unique<Player>(server_->control_port());
    EXPECT_TRUE(idle_->control.connect());
    idle_->control.sign_in("mallory", false);
    for (auto& victim : victims_) victim->join_and_connect(1, server_->game_port());
    mallory_->join_and_connect(1, server_->game_port());
  }

  /// Every player's socket served in turn, a few milliseconds each, until `done` or `limit`.
  template <class Done>
  void play_until(Done done, std::chrono::milliseconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (!done() && std::chrono::steady_clock::now() < until) {
      for (auto& victim : victims_) victim->play_for(4ms);
      if (mallory_->game->transport().state() != proto::ConnectionState::Disconnected) {
        mallory_->play_for(1ms);
      }
    }
  }
  void play_for(std::chrono::milliseconds duration) {
    play_until([] { return false; }, duration);
  }
  std::vector<Seen> seen() const {
    std::vector<Seen> out;
    for (const auto& victim : victims_)
      out.push_back({victim->payloads, victim->newest.server_tick()});
    return out;
  }
  /// The worst victim's share of snapshots since `before` (one per tick), and each connected.
  double worst_snapshot_share(const std::vector<Seen>& before) const {
    double worst = 1;
    for (std::size_t i = 0; i < victims_.size(); ++i) {
      const Player& victim = *victims_[i];
      EXPECT_EQ(victim.game->transport().state(), proto::ConnectionState::Connected)
          << "victim " << i;
      const double ticks = victim.newest.server_tick() - before[i].tick;
      const double share = ticks > 0 ? (victim.payloads - before[i].payloads) / ticks : 0;
      worst = std::min(worst, share);
    }
    return worst;
  }

  std::vector<std::unique_ptr<Player>> victims_;
  std::unique_ptr<Player> mallory_;  ///< plays
  std::unique_ptr<Player> idle_;     ///< mallory, signed in on a second connection
  std::string mallory_token_;
};

TEST_F(AccountBan, ClosesItsConnectionsAtOnceWhileTheOthersPlayOnAndAnUnbanLetsItBack) {
  play_for(300ms);
  const std::vector<Seen> before = seen();

  const auto banned_at = std::chrono::steady_clock::now();
  const HttpResponse ban = http_request(server_->admin_port(), "POST", "/accounts/MALLORY/ban");
  ASSERT_EQ(ban.status, 200) << ban.body;
  EXPECT_NE(ban.body.find("2 control connections closed, taken out of its match"),
            std::string::npos)
      << ban.body;
  play_until(
      [&] { return mallory_->game->transport().state() == proto::ConnectionState::Disconnected; },
      2s);
  const auto disconnected_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                                   std::chrono::steady_clock::now() - banned_at)
                                   .count();
  ASSERT_EQ(mallory_->game->transport().state(), proto::ConnectionState::Disconnected);
  EXPECT_EQ(mallory_->game->transport().disconnect_reason(), proto::DisconnectReason::Banned);
  EXPECT_LT(disconnected_ms, 1000);
  // Both control connections: told ACCOUNT_BANNED, then closed.
  for (Player* session : {mallory_.get(), idle_.get()}) {
    std::vector<wire::ServerMessage> told;
    EXPECT_TRUE(session->control.wait_closed(2s, &told));
    ASSERT_FALSE(told.empty());
    EXPECT_EQ(told.back().error().code(), wire::ACCOUNT_BANNED) << told.back().DebugString();
    EXPECT_EQ(told.back().request_id(), 0u);
  }
  play_for(1000ms);
  const double worst = worst_snapshot_share(before);
  EXPECT_GE(worst, 0.95);
  std::printf(
      "ban: mallory's game connection closed %lld ms after the request; worst victim kept "
      "%.3f of its snapshots\n",
      static_cast<long long>(disconnected_ms), worst);

  // Neither a login nor the session token gets back in.
  Player again(server_->control_port());
  ASSERT_TRUE(again.control.connect());
  EXPECT_EQ(
      again.control.request(ControlTestClient::login("mallory", "password-mallory")).error().code(),
      wire::ACCOUNT_BANNED);
  EXPECT_EQ(again.control.request(ControlTestClient::resume(mallory_token_)).error().code(),
            wire::UNKNOWN_SESSION);

  const std::string page = ricochet::test::admin_get(server_->admin_port(), "/metrics");
  EXPECT_EQ(metric(page, R"(ricochet_account_bans_total{action="ban"})"), 1) << page;
  EXPECT_EQ(metric(page, R"(ricochet_ban_closed_total{what="control_sessions"})"), 2);
  EXPECT_EQ(metric(page, R"(ricochet_ban_closed_total{what="players"})"), 1);
  EXPECT_EQ(metric(page, R"(ricochet_game_disconnects_total{reason="banned"})"), 1);
  EXPECT_EQ(metric(page, R"(ricochet_match_players{match="1",state="connected"})"), 3);

  const HttpResponse unban = http_request(server_->admin_port(), "POST", "/accounts/mallory/unban");
  ASSERT_EQ(unban.status, 200) << unban.body;
  again.control.sign_in("mallory", false);
  again.join_and_connect(1, server_->game_port());
  again.play_for(200ms);
  EXPECT_NE(again.newest.your_entity_id(), 0u);
  EXPECT_EQ(metric(ricochet::test::admin_get(server_->admin_port(), "/metrics"),
                   R"(ricochet_account_bans_total{action="unban"})"),
            1);
}

TEST_F(AccountBan, OfAnUnknownNameOrByGetChangesNothing) {
  EXPECT_EQ(http_request(server_->admin_port(), "POST", "/accounts/nobody/ban").status, 404);
  EXPECT_EQ(http_request(server_->admin_port(), "GET", "/accounts/mallory/ban").status, 405);
  EXPECT_EQ(http_request(server_->admin_port(), "POST", "/accounts/mal%20lory/ban").status, 404);
  play_for(300ms);
  EXPECT_EQ(mallory_->game->transport().state(), proto::ConnectionState::Connected);
  EXPECT_TRUE(mallory_->control.request(ControlTestClient::list_matches()).has_list_matches());
}

TEST(AccountBanAccess, NeedsTheBearerTokenWhenOneIsSet) {
  const TempDir dir("ricochet-e2e-ban-token");
  server::ServerConfig config = test_config(dir.path());
  {
    std::ofstream token(dir.path() / "admin.token");
    token << "s3cret\n";
  }
  config.admin.token_file = (dir.path() / "admin.token").string();
  server::Server server(config);
  server.start();
  Player mallory(server.control_port());
  ASSERT_TRUE(mallory.control.connect());
  mallory.control.sign_in("mallory");
  EXPECT_EQ(http_request(server.admin_port(), "POST", "/accounts/mallory/ban").status, 401);
  EXPECT_EQ(http_request(server.admin_port(), "POST", "/accounts/mallory/ban", "wrong").status,
            401);
  EXPECT_TRUE(mallory.control.request(ControlTestClient::list_matches()).has_list_matches());
  EXPECT_EQ(http_request(server.admin_port(), "POST", "/accounts/mallory/ban", "s3cret").status,
            200);
  EXPECT_TRUE(mallory.control.wait_closed(2s));
}

TEST(ServerMatchEnd, AMatchEndsAtItsTimeLimitIsRecordedAndTheNextMapOfTheRotationOpens) {
  const TempDir dir("ricochet-e2e-end");
  server::ServerConfig config = test_config(dir.path());
  config.matches.count = 1;
  config.matches.maps.push_back(RICOCHET_SOURCE_DIR "/server/maps/foundry.toml");
  config.matches.time_limit_s = 1.5;
  auto server = std::make_unique<server::Server>(config);
  server->start();
  const auto signed_in = [&server](const std::string& name) {
    auto player = std::make_unique<Player>(server->control_port());
    EXPECT_TRUE(player->control.connect());
    player->control.sign_in(name);
    return player;
  };
  auto alice = signed_in("alice");
  alice->join_and_connect(1, server->game_port());
  alice->buttons = 1u << 1;  // fire held: the rifle's shots count
  // Running from her arrival (min_players 1, no warm-up) until the 1.5 s limit; then the match
  // tells her it ended and closes her game connection.
  const auto until = std::chrono::steady_clock::now() + 6s;
  while (alice->game->transport().state() != proto::ConnectionState::Disconnected &&
         std::chrono::steady_clock::now() < until) {
    alice->play_for(50ms);
  }
  ASSERT_EQ(alice->game->transport().state(), proto::ConnectionState::Disconnected);
  EXPECT_EQ(alice->game->transport().disconnect_reason(), proto::DisconnectReason::Kicked);
  bool told_match_ended = false;
  for (const wire::GameEvent& event : alice->game_events) {
    if (event.has_match_ended()) {
      told_match_ended = true;
      EXPECT_EQ(event.match_ended().reason(), wire::MATCH_END_REASON_TIME_LIMIT);
    }
  }
  EXPECT_TRUE(told_match_ended);

  // The results, once the record is written, over TLS.
  const auto results = alice->control.receive(5s);
  ASSERT_TRUE(results && results->has_match_results())
      << (results ? results->DebugString() : "nothing");
  const wire::MatchResults& match = results->match_results();
  EXPECT_EQ(match.match_id(), 1u);
  EXPECT_EQ(match.map(), "arena");
  EXPECT_EQ(match.mode(), "ffa");
  EXPECT_FALSE(match.aborted());
  EXPECT_EQ(match.end_reason(), wire::MATCH_END_REASON_TIME_LIMIT);
  ASSERT_EQ(match.players_size(), 1);
  const wire::PlayerMatchResult& player = match.players(0);
  EXPECT_EQ(player.username(), "alice");
  EXPECT_EQ(player.team(), wire::TEAM_NONE);
  EXPECT_GT(player.shots(), 0);
  EXPECT_EQ(player.hits(), 0);  // nobody else to hit
  EXPECT_GT(player.seconds_played(), 1.0);
  EXPECT_EQ(player.rank(), 1u);
  EXPECT_TRUE(player.won());  // the top score, alone

  // Followed by a match on the rotation's next map, which she can join.
  const wire::ServerMessage list = alice->control.request(ControlTestClient::list_matches());
  ASSERT_TRUE(list.has_list_matches());
  ASSERT_EQ(list.list_matches().matches_size(), 1);
  const wire::MatchInfo& next = list.list_matches().matches(0);
  EXPECT_EQ(next.match_id(), 2u);
  EXPECT_EQ(next.map(), "foundry");
  EXPECT_EQ(next.name(), "ffa-1");
  alice->newest = {};
  alice->sequence = 0;
  alice->join_and_connect(2, server->game_port());
  alice->play_for(200ms);
  EXPECT_NE(alice->newest.your_entity_id(), 0u);

  // The recording, written off the match's strand.
  std::vector<std::filesystem::path> recordings;
  const auto recordings_dir = dir.path() / "recordings";
  for (int attempt = 0; attempt < 100 && recordings.empty(); ++attempt) {
    if (std::filesystem::exists(recordings_dir)) {
      for (const auto& entry : std::filesystem::directory_iterator(recordings_dir)) {
        if (entry.path().extension() == ".rcr") recordings.push_back(entry.path());
      }
    }
    if (recordings.empty()) std::this_thread::sleep_for(20ms);
  }
  ASSERT_EQ(recordings.size(), 1u);
  EXPECT_EQ(recordings[0].filename().string().rfind("match-1-", 0), 0u) << recordings[0];
  EXPECT_GT(std::filesystem::file_size(recordings[0]), 0u);
  // ... which re-simulates the match bit for bit (every recorded hash matches).
  std::ifstream file(recordings[0], std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(file),
                                        std::istreambuf_iterator<char>()};
  auto read = server::read_recording(bytes);
  ASSERT_TRUE(std::holds_alternative<server::Recording>(read))
      << std::get<server::RecordingError>(read).message;
  const server::Recording& recording = std::get<server::Recording>(read);
  EXPECT_TRUE(recording.complete);
  auto opened = server::open_recorded_match(recording);
  ASSERT_TRUE(std::holds_alternative<server::Match>(opened)) << std::get<std::string>(opened);
  server::MatchSimulation simulation(std::get<server::Match>(opened));
  const server::ReplayReport replayed = server::replay(recording, simulation);
  EXPECT_GT(replayed.hashes_checked, 0u);
  EXPECT_FALSE(replayed.first_mismatch)
      << "first mismatch at tick " << replayed.first_mismatch->tick;
  EXPECT_EQ(std::get<server::Match>(opened).scoreboard().at(0).shots, player.shots());
  const std::string page = ricochet::test::admin_get(server->admin_port(), "/metrics");
  EXPECT_EQ(metric(page, R"(ricochet_recordings_total{result="written"})"), 1) << page;
  EXPECT_EQ(metric(page, "ricochet_matches"), 1);  // the one that followed

  server->stop();
  EXPECT_EQ(server->wait(), 0);
  server.reset();
  const std::optional<db::PlayerStats> stats = stats_of(dir.file("ricochet.db"), "alice");
  ASSERT_TRUE(stats);
  // The first match, and the second, stopped by the server (aborted: counted, but no win).
  EXPECT_EQ(stats->matches, 2);
  EXPECT_EQ(stats->wins, 1);
  EXPECT_GE(stats->shots, player.shots());
  EXPECT_GT(stats->seconds_played, player.seconds_played());
}

TEST(ServerMatchEnd, ATeamDeathmatchEndsWithTheTeamsScoresAndEveryPlayerOnATeam) {
  const TempDir dir("ricochet-e2e-tdm");
  server::ServerConfig config = test_config(dir.path());
  config.matches.count = 1;
  config.matches.mode = "tdm";
  config.matches.time_limit_s = 1.0;
  config.matches.record = false;
  auto server = std::make_unique<server::Server>(config);
  server->start();
  std::vector<std::unique_ptr<Player>> players;
  // Both sign in before either joins: the one-second clock starts with the first player, and
  // a sign-in on a loaded machine can take longer than that.
  for (const char* name : {"alice", "bob"}) {
    players.push_back(std::make_unique<Player>(server->control_port()));
    ASSERT_TRUE(players.back()->control.connect());
    players.back()->control.sign_in(name);
  }
  for (const auto& player : players) {
    ASSERT_NO_FATAL_FAILURE(player->join_and_connect(1, server->game_port()));
  }
  // Both play in turns until the limit ends the match and each is let go.
  const auto until = std::chrono::steady_clock::now() + 6s;
  const auto all_gone = [&players] {
    for (const auto& player : players) {
      if (player->game->transport().state() != proto::ConnectionState::Disconnected) return false;
    }
    return true;
  };
  while (!all_gone() && std::chrono::steady_clock::now() < until) {
    for (const auto& player : players) player->play_for(20ms);
  }
  ASSERT_TRUE(all_gone());
  for (const auto& player : players) {
    const auto results = player->control.receive(5s);
    ASSERT_TRUE(results && results->has_match_results())
        << (results ? results->DebugString() : "nothing");
    const wire::MatchResults& match = results->match_results();
    EXPECT_EQ(match.mode(), "tdm");
    EXPECT_FALSE(match.aborted());
    EXPECT_EQ(match.end_reason(), wire::MATCH_END_REASON_TIME_LIMIT);
    ASSERT_EQ(match.team_scores_size(), 2);
    EXPECT_EQ(match.team_scores(0).team(), wire::TEAM_RED);
    EXPECT_EQ(match.team_scores(1).team(), wire::TEAM_BLUE);
    ASSERT_EQ(match.players_size(), 2);
    // Balanced on join: one on each side.
    EXPECT_NE(match.players(0).team(), match.players(1).team());
    for (const wire::PlayerMatchResult& result : match.players()) {
      EXPECT_TRUE(result.team() == wire::TEAM_RED || result.team() == wire::TEAM_BLUE);
    }
  }
  server->stop();
  EXPECT_EQ(server->wait(), 0);
}

/// Starts a server on `config` that must refuse to start with an error containing `expected`,
/// and stop at once (no grace period to wait out).
void expect_start_refused(const server::ServerConfig& config, const std::string& expected) {
  const auto started = std::chrono::steady_clock::now();
  {
    server::Server server(config);
    try {
      server.start();
      ADD_FAILURE() << "start() succeeded; expected \"" << expected << "\"";
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
    }
  }
  EXPECT_LT(std::chrono::steady_clock::now() - started, 3s);
}

TEST(ServerStart, APortInUseIsAClearErrorAndTheServerStopsAtOnce) {
  const TempDir dir("ricochet-e2e-port");
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor taken(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  server::ServerConfig config = test_config(dir.path());
  config.control.port = taken.local_endpoint().port();
  expect_start_refused(config, "control channel (TLS) on 127.0.0.1:");
}

TEST(ServerStart, APortsFileThatCannotBeWrittenIsAClearErrorAndTheServerStopsAtOnce) {
  const TempDir dir("ricochet-e2e-ports-file");
  server::ServerConfig config = test_config(dir.path());
  config.server.ports_file = (dir.path() / "no-such-directory" / "ports.json").string();
  expect_start_refused(config, "cannot write the ports file");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "no-such-directory"));
}

/// What the server logs at warn and above while it starts with `config` and stops.
std::string start_log(const server::ServerConfig& config) {
  std::ostringstream text;
  auto previous = spdlog::default_logger();
  auto capture = std::make_shared<spdlog::logger>(
      "capture", std::make_shared<spdlog::sinks::ostream_sink_mt>(text));
  capture->set_level(spdlog::level::warn);
  spdlog::set_default_logger(capture);
  {
    server::Server server(config);
    server.start();
    server.stop();
    EXPECT_EQ(server.wait(), 0);
  }
  spdlog::set_default_logger(previous);
  return text.str();
}

// Issue 29: the minimum hashing cost, meant for load tests, started as quietly as the real one.
TEST(ServerStart, MinimumPasswordHashingIsALoudWarning) {
  const TempDir dir("ricochet-e2e-hashing");
  server::ServerConfig config = test_config(dir.path());
  EXPECT_EQ(start_log(config).find("password_hashing"), std::string::npos);
  config.db.password_hashing = server::PasswordHashing::Minimum;
  const std::string log = start_log(config);
  EXPECT_NE(log.find("password_hashing = \"minimum\""), std::string::npos) << log;
  EXPECT_NE(log.find("never with real players' accounts"), std::string::npos) << log;
}

}  // namespace
}  // namespace ricochet::test::server_end_to_end_test
