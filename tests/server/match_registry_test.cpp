// The match registry's seats: joining reserves one and issues a token, a full match refuses, one
// match at a time, leaving frees the seat, a reservation whose token went unused is given back,
// and a closed registry refuses joins and creates. Over a real GameChannel on 127.0.0.1:0 (no
// client connects; the registry is driven through its MatchDirectory face); seats and tokens
// run on a fake clock the tests move.
#include "match_registry.h"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <map>
#include <memory>
#include <variant>

#include "game_channel.h"
#include "ricochet/proto/connect_token.h"

namespace ricochet::server {
namespace {

using namespace std::chrono_literals;

Map sample_map() {
  auto loaded = load_map_file(RICOCHET_SOURCE_DIR "/server/maps/arena.toml");
  if (auto* error = std::get_if<MapError>(&loaded)) ADD_FAILURE() << error->describe();
  return std::get<Map>(std::move(loaded));
}

class MatchRegistryTest : public ::testing::Test {
 protected:
  explicit MatchRegistryTest(proto::TimeUs token_lifetime_us = 10 * proto::kMicrosPerSecond) {
    GameChannelConfig channel;
    channel.bind = "127.0.0.1";
    channel.port = 0;
    channel.transport.protocol_id = proto::kProtocolId;
    channel_ = std::make_unique<GameChannel>(io_, channel);
    MatchRegistryConfig config;
    config.token_lifetime_us = token_lifetime_us;
    config.token_timeout_s = 1;
    config.max_matches = 3;
    config.clock = [this] { return now_; };
    // A rotation of two maps: the arena, and the arena again under another name.
    Map second = sample_map();
    second.name = "arena-b";
    std::vector<Map> rotation;
    rotation.push_back(sample_map());
    rotation.push_back(std::move(second));
    registry_ = std::make_unique<MatchRegistry>(io_, config, std::move(rotation), *channel_,
                                                [](EndedMatch) {});
    channel_->start(*registry_);
    registry_->set_udp_port(channel_->port());
  }
  ~MatchRegistryTest() override {
    channel_->stop();
    io_.run_for(100ms);  // the stop, and the matches' first ticks, run here
  }

  std::uint32_t open(const std::string& name, int max_players) {
    auto opened = registry_->open(name, max_players);
    EXPECT_TRUE(std::holds_alternative<MatchSummary>(opened));
    return std::get<MatchSummary>(opened).id;
  }
  DirectoryErrorCode refusal(const DirectoryResult<JoinGrant>& result) {
    EXPECT_TRUE(std::holds_alternative<DirectoryError>(result));
    return std::holds_alternative<DirectoryError>(result) ? std::get<DirectoryError>(result).code
                                                          : DirectoryErrorCode::InvalidRequest;
  }
  int players_in(std::uint32_t match) {
    for (const MatchSummary& summary : registry_->list()) {
      if (summary.id == match) return summary.players;
    }
    return -1;
  }

  proto::TimeUs now_ = 100 * proto::kMicrosPerSecond;  ///< the seats' fake clock
  boost::asio::io_context io_;
  std::unique_ptr<GameChannel> channel_;
  std::unique_ptr<MatchRegistry> registry_;
};

TEST_F(MatchRegistryTest, JoiningReservesASeatAndIssuesAnOpenableToken) {
  const std::uint32_t match = open("a", 4);
  auto joined = registry_->join(7, "seven", match);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(joined));
  const JoinGrant& grant = std::get<JoinGrant>(joined);
  EXPECT_EQ(grant.match_id, match);
  EXPECT_EQ(grant.udp_port, channel_->port());
  EXPECT_EQ(grant.tick_rate_hz, 60);
  EXPECT_EQ(grant.token.expires_at, now_ + 10 * proto::kMicrosPerSecond);  // on its clock
  EXPECT_TRUE(grant.quantization.validate().empty());
  // Sealed under the registry's key (zero here), bound to the account and the match.
  const auto opened = proto::open_connect_token(
      proto::Key{}, proto::kProtocolId, grant.token.connect_token, grant.token.expires_at - 1);
  ASSERT_TRUE(opened.ok());
  EXPECT_EQ(opened.value.contents.account_id, 7u);
  EXPECT_EQ(opened.value.contents.match_id, match);
  EXPECT_EQ(players_in(match), 1);
  EXPECT_EQ(registry_->seats(), 1u);
  // Joining the same match again is a reconnect: a new token, still one seat.
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match)));
  EXPECT_EQ(players_in(match), 1);
}

TEST_F(MatchRegistryTest, AnAccountGetsItsUnusedTokenAgainWithinTheReuseWindow) {
  const std::uint32_t match = open("a", 4);
  const auto token_of = [&](std::uint64_t account) {
    auto joined = registry_->join(account, "someone", match);
    EXPECT_TRUE(std::holds_alternative<JoinGrant>(joined));
    return std::holds_alternative<JoinGrant>(joined)
               ? std::get<JoinGrant>(joined).token.connect_token
               : std::vector<std::uint8_t>{};
  };
  const auto first = token_of(7);
  now_ += proto::kMicrosPerSecond - 1;
  EXPECT_EQ(token_of(7), first) << "however many sessions ask, one token a second";
  EXPECT_NE(token_of(8), first) << "another account's is its own";
  now_ += 1;
  const auto second = token_of(7);
  EXPECT_NE(second, first) << "the window passed";
  registry_->connected(7, match);
  EXPECT_NE(token_of(7), second) << "a token a connection used is never given again";
}

TEST_F(MatchRegistryTest, AWakeUpsPayloadsReachEachPlayersMatchAndNoOther) {
  const std::uint32_t first = open("a", 4);
  const std::uint32_t second = open("b", 4);
  for (const std::uint64_t account : {1, 2}) {
    ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(account, "p", first)));
  }
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "p", second)));
  // Seated but never connected over the game channel: each match counts what it is handed as
  // from an unknown player. Account 99 has no seat, so no match is handed its payload.
  std::vector<GamePayload> batch;
  for (const std::uint64_t account : {1, 3, 99, 2, 1}) batch.push_back({account, {0x0a, 0x00}, 0});
  registry_->payloads(std::move(batch));
  // The posts run, then the matches' next ticks publish their counters.
  std::map<std::uint32_t, std::uint64_t> handed;
  const auto count_handed = [&] {
    for (const auto& host : registry_->hosts()) {
      const auto& drops = host->stats().counters.input_drops;
      handed[host->id()] = drops[static_cast<std::size_t>(InputDrop::UnknownPlayer)];
    }
    return handed[first] == 3 && handed[second] == 1;
  };
  for (int i = 0; i < 1000 && !count_handed(); ++i) io_.run_for(5ms);
  EXPECT_EQ(handed[first], 3u);
  EXPECT_EQ(handed[second], 1u);
}

TEST_F(MatchRegistryTest, AFullMatchRefusesAndLeavingGivesTheSeatBack) {
  const std::uint32_t match = open("duel", 2);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", match)));
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "two", match)));
  EXPECT_EQ(refusal(registry_->join(3, "three", match)), DirectoryErrorCode::MatchFull);
  ASSERT_TRUE(std::holds_alternative<Done>(registry_->leave(1)));
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "three", match)));
  EXPECT_TRUE(std::holds_alternative<DirectoryError>(registry_->leave(1)));  // not in a match
}

TEST_F(MatchRegistryTest, OneMatchAtATimeAndUnknownMatchesAreErrors) {
  const std::uint32_t first = open("a", 4);
  const std::uint32_t second = open("b", 4);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", first)));
  EXPECT_EQ(refusal(registry_->join(1, "one", second)), DirectoryErrorCode::AlreadyInMatch);
  EXPECT_EQ(refusal(registry_->join(2, "two", 999)), DirectoryErrorCode::MatchNotFound);
}

TEST_F(MatchRegistryTest, CreateValidatesItsFieldsAndTheMatchCap) {
  const auto invalid = [this](CreateMatchRequest request) {
    auto result = registry_->create(request);
    return std::holds_alternative<DirectoryError>(result) &&
           std::get<DirectoryError>(result).code == DirectoryErrorCode::InvalidRequest;
  };
  EXPECT_TRUE(invalid({.name = "", .max_players = 4, .map = ""}));
  EXPECT_TRUE(invalid({.name = "ok", .max_players = 0, .map = ""}));
  EXPECT_TRUE(invalid({.name = "ok", .max_players = 65, .map = ""}));
  EXPECT_TRUE(invalid({.name = "ok", .max_players = 4, .map = "elsewhere"}));
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(std::holds_alternative<MatchSummary>(
        registry_->create({.name = "m", .max_players = 4, .map = ""})));
  }
  auto fourth = registry_->create({.name = "m", .max_players = 4, .map = ""});
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(fourth));
  EXPECT_EQ(std::get<DirectoryError>(fourth).code, DirectoryErrorCode::TooManyMatches);
}

TEST_F(MatchRegistryTest, MatchesArePlayedOnTheRotationsMaps) {
  const auto map_of = [this](std::uint32_t id) {
    for (const MatchSummary& summary : registry_->list())
      if (summary.id == id) return summary.map;
    return std::string("none");
  };
  const std::uint32_t first = open("a", 4);
  EXPECT_EQ(map_of(first), "arena");
  auto named = registry_->create({.name = "b", .max_players = 4, .map = "arena-b"});
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(named));
  EXPECT_EQ(std::get<MatchSummary>(named).map, "arena-b");
  EXPECT_EQ(registry_->next_in_rotation(0), 1u);
  EXPECT_EQ(registry_->next_in_rotation(1), 0u);  // back to the first
  auto next = registry_->open("c", 4, registry_->next_in_rotation(1));
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(next));
  EXPECT_EQ(std::get<MatchSummary>(next).map, "arena");
  auto unknown = registry_->create({.name = "d", .max_players = 4, .map = "foundry"});
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(unknown));
  EXPECT_EQ(std::get<DirectoryError>(unknown).message,
            "map must be one of the loaded maps ('arena', 'arena-b') or empty, got 'foundry'");
}

TEST_F(MatchRegistryTest, AClosedRegistryRefusesJoinsAndCreates) {
  const std::uint32_t match = open("a", 4);
  registry_->close();
  EXPECT_EQ(refusal(registry_->join(1, "one", match)), DirectoryErrorCode::ShuttingDown);
  auto created = registry_->create({.name = "late", .max_players = 4, .map = ""});
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(created));
  EXPECT_EQ(std::get<DirectoryError>(created).code, DirectoryErrorCode::ShuttingDown);
}

class ShortTokenRegistryTest : public MatchRegistryTest {
 protected:
  ShortTokenRegistryTest() : MatchRegistryTest(50 * proto::kMicrosPerMilli) {}
};

TEST_F(ShortTokenRegistryTest, AReservationWhoseTokenWentUnusedIsGivenBack) {
  const std::uint32_t match = open("duel", 1);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", match)));
  EXPECT_EQ(refusal(registry_->join(2, "two", match)), DirectoryErrorCode::MatchFull);
  // The token lives 50 ms, plus its 1 s timeout for a handshake accepted at the last moment.
  now_ += 1050 * proto::kMicrosPerMilli - 1;
  EXPECT_EQ(players_in(match), 1);
  EXPECT_EQ(refusal(registry_->join(2, "two", match)), DirectoryErrorCode::MatchFull);
  now_ += 1;
  EXPECT_EQ(players_in(match), 0);
  EXPECT_EQ(registry_->seats(), 0u);
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "two", match)));
}

}  // namespace
}  // namespace ricochet::server
