// The match registry's seats: joining reserves one and issues a token, a full match refuses, one
// match at a time, leaving frees the seat, a reservation whose token went unused is given back,
// and a closed registry refuses joins and creates. The limits: seats per address (IPv6 by /64),
// seats of a match waiting for their player, one session per account, created matches per
// account and server-wide and their rate, and created matches closed when empty too long. Over a
// real GameChannel on 127.0.0.1:0 (no client connects; the registry is driven through its
// MatchDirectory face); seats and tokens run on a fake clock the tests move.
#include "match_registry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <map>
#include <memory>
#include <variant>

#include "game_channel.h"
#include "ricochet/proto/connect_token.h"

namespace ricochet::server::match_registry_test {
namespace {

using namespace std::chrono_literals;

Map sample_map() {
  auto loaded = load_map_file(RICOCHET_SOURCE_DIR "/server/maps/arena.toml");
  if (auto* error = std::get_if<MapError>(&loaded)) ADD_FAILURE() << error->describe();
  return std::get<Map>(std::move(loaded));
}

/// Joins from one session on 127.0.0.1 (the limits' tests below give other origins).
const JoinOrigin kHere{proto::host_key(proto::Address::ipv4(127, 0, 0, 1, 0)), 1};

class MatchRegistryTest : public ::testing::Test {
 protected:
  explicit MatchRegistryTest(proto::TimeUs token_lifetime_us = 10 * proto::kMicrosPerSecond,
                             SeatLimits limits = {}) {
    GameChannelConfig channel;
    channel.bind = "127.0.0.1";
    channel.port = 0;
    channel.transport.protocol_id = proto::kProtocolId;
    channel_ = std::make_unique<GameChannel>(io_, channel);
    MatchRegistryConfig config;
    config.token_lifetime_us = token_lifetime_us;
    config.token_timeout_s = 1;
    config.max_matches = 3;
    config.limits = limits;
    config.clock = [this] { return now_; };
    // A rotation of two maps: the arena, and the arena again under another name.
    Map second = sample_map();
    second.name = "arena-b";
    std::vector<Map> rotation;
    rotation.push_back(sample_map());
    rotation.push_back(std::move(second));
    registry_ = std::make_unique<MatchRegistry>(io_, config, std::move(rotation), *channel_,
                                                [this](EndedMatch) { ++ended_; });
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

  bool listed(std::uint32_t match) {
    const auto all = registry_->list();
    return std::any_of(all.begin(), all.end(), [&](const auto& m) { return m.id == match; });
  }

  proto::TimeUs now_ = 100 * proto::kMicrosPerSecond;  ///< the seats' fake clock
  std::atomic<int> ended_{0};                          ///< matches handed to the MatchEndedHandler
  boost::asio::io_context io_;
  std::unique_ptr<GameChannel> channel_;
  std::unique_ptr<MatchRegistry> registry_;
};

TEST_F(MatchRegistryTest, JoiningReservesASeatAndIssuesAnOpenableToken) {
  const std::uint32_t match = open("a", 4);
  auto joined = registry_->join(7, "seven", match, kHere);
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
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match, kHere)));
  EXPECT_EQ(players_in(match), 1);
}

TEST_F(MatchRegistryTest, AnAccountGetsItsUnusedTokenAgainWithinTheReuseWindow) {
  const std::uint32_t match = open("a", 4);
  const auto token_of = [&](std::uint64_t account) {
    auto joined = registry_->join(account, "someone", match, kHere);
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
    ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(account, "p", first, kHere)));
  }
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "p", second, kHere)));
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
  // Each connects before the next joins: half the seats may wait for their player at most.
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", match, kHere)));
  registry_->connected(1, match);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "two", match, kHere)));
  registry_->connected(2, match);
  EXPECT_EQ(refusal(registry_->join(3, "three", match, kHere)), DirectoryErrorCode::MatchFull);
  ASSERT_TRUE(std::holds_alternative<Done>(registry_->leave(1, 1)));
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "three", match, kHere)));
  EXPECT_TRUE(std::holds_alternative<DirectoryError>(registry_->leave(1, 1)));  // not in a match
}

TEST_F(MatchRegistryTest, SeatsHeldByPlacementTicketsCountAgainstDirectJoinsOnly) {
  const std::uint32_t match = open("duel", 3);
  const std::uint32_t other = open("other", 3);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", match, kHere)));
  registry_->connected(1, match);
  // Two seats of the match held by open tickets (and one for a new match: no match of its own).
  registry_->set_held_seats({{match, 2}, {999, 3}});
  EXPECT_EQ(refusal(registry_->join(2, "two", match, kHere)), DirectoryErrorCode::MatchFull);
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "three", other, kHere)));
  // A ticket's player takes one of the held seats.
  JoinOrigin placed = kHere;
  placed.placed = true;
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "two", match, placed)));
  registry_->connected(2, match);
  // The tickets went (claimed or expired): a direct join fits again.
  registry_->set_held_seats({});
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(4, "four", match, kHere)));
}

TEST_F(MatchRegistryTest, OneMatchAtATimeAndUnknownMatchesAreErrors) {
  const std::uint32_t first = open("a", 4);
  const std::uint32_t second = open("b", 4);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", first, kHere)));
  EXPECT_EQ(refusal(registry_->join(1, "one", second, kHere)), DirectoryErrorCode::AlreadyInMatch);
  EXPECT_EQ(refusal(registry_->join(2, "two", 999, kHere)), DirectoryErrorCode::MatchNotFound);
}

// Issue 29: a session replaced by a newer join of the account still chatted as it, and a line
// sent while the game connection was away was accepted and then dropped by the match unseen.
TEST_F(MatchRegistryTest, OnlyTheSessionThatPlaysTheAccountChatsAndOnlyWhileConnected) {
  const std::uint32_t match = open("a", 4);
  const auto chat = [this](std::uint64_t session) {
    const auto result = registry_->chat(7, session, "hello");
    return std::holds_alternative<DirectoryError>(result)
               ? std::optional(std::get<DirectoryError>(result))
               : std::nullopt;
  };
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match, kHere)));
  ASSERT_TRUE(chat(kHere.session));  // reserved, no game connection yet
  EXPECT_EQ(chat(kHere.session)->code, DirectoryErrorCode::NotInMatch);
  EXPECT_NE(chat(kHere.session)->message.find("game connection is not up"), std::string::npos);
  registry_->connected(7, match);
  EXPECT_FALSE(chat(kHere.session));
  // Another session takes the seat over: the first one no longer speaks for the account.
  const JoinOrigin newer{kHere.host, 2};
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match, newer)));
  registry_->connected(7, match);
  ASSERT_TRUE(chat(kHere.session));
  EXPECT_NE(chat(kHere.session)->message.find("another control connection"), std::string::npos);
  EXPECT_FALSE(chat(newer.session));
  registry_->disconnected(7, proto::DisconnectReason::TimedOut);  // away, within the grace
  ASSERT_TRUE(chat(newer.session));
  EXPECT_EQ(chat(newer.session)->code, DirectoryErrorCode::NotInMatch);
}

// Issue 30: a control connection resumed after a loss was signed in but not in its match; the
// sign-in that joined (the same session token) takes its seat back, nobody else does.
TEST_F(MatchRegistryTest, AResumeOfTheSignInThatJoinedTakesTheSeatBack) {
  const std::uint32_t match = open("a", 4);
  const JoinOrigin phone{kHere.host, 1, std::string(64, 'a')};
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match, phone)));
  registry_->connected(7, match);
  // Another sign-in of the account, a seatless account, a connection not signed in: nothing.
  EXPECT_FALSE(registry_->rejoin(7, JoinOrigin{kHere.host, 2, std::string(64, 'b')}));
  EXPECT_FALSE(registry_->rejoin(8, JoinOrigin{kHere.host, 2, phone.session_token}));
  EXPECT_FALSE(registry_->rejoin(7, JoinOrigin{kHere.host, 2}));
  EXPECT_TRUE(std::holds_alternative<DirectoryError>(registry_->leave(7, 2)))
      << "session 2 never played the seat";

  // On mobile now: another address, a new control connection, the same token.
  const JoinOrigin resumed{proto::host_key(proto::Address::ipv4(10, 0, 0, 2, 0)), 3,
                           phone.session_token};
  EXPECT_EQ(registry_->rejoin(7, resumed), std::optional<std::uint32_t>(match));
  EXPECT_EQ(players_in(match), 1);
  // The game connection is still the seat's (chat needs it up); the resumed session plays it,
  // the lost one no longer does.
  EXPECT_TRUE(std::holds_alternative<Done>(registry_->chat(7, resumed.session, "back")));
  const auto ghost = registry_->chat(7, phone.session, "ghost");
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(ghost));
  EXPECT_NE(std::get<DirectoryError>(ghost).message.find("another control connection"),
            std::string::npos);
  EXPECT_TRUE(std::holds_alternative<DirectoryError>(registry_->leave(7, phone.session)));
  // A join from the resumed session is a plain reconnect (no move, no kick), then it leaves.
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match, resumed)));
  EXPECT_TRUE(std::holds_alternative<Done>(registry_->leave(7, resumed.session)));
  EXPECT_EQ(registry_->seats(), 0u);
  EXPECT_FALSE(registry_->rejoin(7, resumed)) << "the seat is gone";
}

TEST_F(MatchRegistryTest, AResumeAfterTheReservationRanOutIsNotInTheMatch) {
  const std::uint32_t match = open("a", 4);
  const JoinOrigin phone{kHere.host, 1, std::string(64, 'a')};
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(7, "seven", match, phone)));
  // Reserved, never connected: held while its token (10 s) and the handshake's timeout (1 s) run.
  now_ += 10 * proto::kMicrosPerSecond;
  EXPECT_EQ(registry_->rejoin(7, JoinOrigin{kHere.host, 2, phone.session_token}),
            std::optional<std::uint32_t>(match));
  now_ += 2 * proto::kMicrosPerSecond;
  EXPECT_FALSE(registry_->rejoin(7, JoinOrigin{kHere.host, 3, phone.session_token}));
  EXPECT_EQ(registry_->seats(), 0u);
}

// Issue 29: created matches' names let bidi overrides through (listed to every player).
TEST_F(MatchRegistryTest, AMatchNameFollowsTheChatTextRule) {
  const auto refusal = [this](const std::string& name) -> std::string {
    auto result = registry_->create({.name = name, .max_players = 4, .map = "", .creator = 1});
    return std::holds_alternative<DirectoryError>(result) ? std::get<DirectoryError>(result).message
                                                          : "";
  };
  EXPECT_NE(refusal("\xE2\x80\xAE"
                    "evil"),
            "");                                    // U+202E right-to-left override
  EXPECT_NE(refusal("zero\xE2\x80\x8Bwidth"), "");  // U+200B zero width space
  EXPECT_NE(refusal("tab\there"), "");
  EXPECT_NE(refusal("\xC3"), "");  // cut UTF-8
  EXPECT_NE(refusal(std::string(33, 'a')), "");
  EXPECT_EQ(refusal("caf\xC3\xA9 du coin"), "");
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
  for (std::uint64_t creator = 1; creator <= 3; ++creator) {
    EXPECT_TRUE(std::holds_alternative<MatchSummary>(
        registry_->create({.name = "m", .max_players = 4, .map = "", .creator = creator})));
  }
  auto fourth = registry_->create({.name = "m", .max_players = 4, .map = "", .creator = 4});
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
  EXPECT_EQ(refusal(registry_->join(1, "one", match, kHere)), DirectoryErrorCode::ShuttingDown);
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
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "one", match, kHere)));
  EXPECT_EQ(refusal(registry_->join(2, "two", match, kHere)), DirectoryErrorCode::MatchFull);
  // The token lives 50 ms, plus its 1 s timeout for a handshake accepted at the last moment.
  now_ += 1050 * proto::kMicrosPerMilli - 1;
  EXPECT_EQ(players_in(match), 1);
  EXPECT_EQ(refusal(registry_->join(2, "two", match, kHere)), DirectoryErrorCode::MatchFull);
  now_ += 1;
  EXPECT_EQ(players_in(match), 0);
  EXPECT_EQ(registry_->seats(), 0u);
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "two", match, kHere)));
}

JoinOrigin from(std::uint8_t last_octet, std::uint64_t session = 1) {
  return {proto::host_key(proto::Address::ipv4(10, 0, 0, last_octet, 40000)), session};
}

SeatLimits tight_limits() {
  SeatLimits limits;
  limits.seats_per_address = 2;
  limits.reserved_seats_per_match = 2;
  limits.created_matches = 2;
  limits.created_matches_per_account = 1;
  limits.creates_per_minute = 600;
  limits.creates_per_account_per_minute = 2;
  limits.empty_match_close_after_us = 60 * proto::kMicrosPerSecond;
  return limits;
}

class LimitedRegistryTest : public MatchRegistryTest {
 protected:
  LimitedRegistryTest() : MatchRegistryTest(10 * proto::kMicrosPerSecond, tight_limits()) {}
};

TEST_F(LimitedRegistryTest, OneAddressHoldsAtMostItsSeatsAcrossMatches) {
  const std::uint32_t first = open("a", 8);
  const std::uint32_t second = open("b", 8);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "p", first, from(1))));
  registry_->connected(1, first);  // taken seats count too, not only reservations
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "p", second, from(1))));
  EXPECT_EQ(refusal(registry_->join(3, "p", second, from(1))),
            DirectoryErrorCode::AddressSeatLimit);
  EXPECT_EQ(registry_->refused(SeatRefusal::AddressSeats), 1u);
  // Another address is not held back, and the address's own seats re-join (a new token).
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "p", second, from(2))));
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "p", second, from(1))));
  registry_->connected(2, second);
  registry_->connected(3, second);
  // An IPv6 peer counts under its /64: two addresses of one prefix share the limit.
  proto::Address v6;
  v6.v6 = true;
  v6.ip = {0x20, 0x01, 0x0d, 0xb8, 0, 0, 0, 1};
  const JoinOrigin low{proto::host_key(v6), 1};
  v6.ip[15] = 0x99;
  const JoinOrigin high{proto::host_key(v6), 1};
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(10, "p", second, low)));
  registry_->connected(10, second);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(11, "p", second, high)));
  registry_->connected(11, second);
  EXPECT_EQ(refusal(registry_->join(12, "p", second, high)), DirectoryErrorCode::AddressSeatLimit);
}

TEST_F(LimitedRegistryTest, AMatchWaitsForAtMostItsReservedSeatsAtOnce) {
  const auto ms = [](int n) { return n * proto::kMicrosPerMilli; };
  const std::uint32_t match = open("a", 8);  // waits for 2 reservations at most (tight_limits)
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "p", match, from(1))));
  now_ += ms(100);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(2, "p", match, from(2))));
  EXPECT_EQ(refusal(registry_->join(3, "p", match, from(3))), DirectoryErrorCode::MatchFull);
  EXPECT_EQ(registry_->refused(SeatRefusal::ReservedSeats), 1u);
  // One of them connects: its seat is taken, no longer reserved, and the next may reserve.
  registry_->connected(1, match);
  now_ += ms(400);
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "p", match, from(3))));
  EXPECT_EQ(players_in(match), 3);
  // At the bound again, a reservation unused for a second gives way: account 2's (1 s old),
  // not account 3's (0.6 s).
  now_ += ms(600);
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(4, "p", match, from(4))));
  EXPECT_EQ(players_in(match), 3);
  EXPECT_EQ(registry_->refused(SeatRefusal::ReservedSeats), 2u);
  EXPECT_EQ(refusal(registry_->join(5, "p", match, from(5))), DirectoryErrorCode::MatchFull);
  // Joining again does not make a reservation younger: account 3's gives way at 1 s.
  now_ += ms(400);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(3, "p", match, from(3))));
  EXPECT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(5, "p", match, from(5))));
  EXPECT_EQ(players_in(match), 3);  // 1 connected, 4 and 5 reserved
  // Account 2's token finds no seat now: its game connection would be kicked.
  EXPECT_EQ(refusal(registry_->join(2, "p", match, from(2))), DirectoryErrorCode::MatchFull);
}

TEST_F(LimitedRegistryTest, TheNewestSessionPlaysTheAccount) {
  const std::uint32_t match = open("a", 8);
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "p", match, from(1, 100))));
  registry_->connected(1, match);
  // A second control connection of the account joins the same match: it takes the seat over
  // (no second seat); the first one's leave no longer applies.
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "p", match, from(2, 200))));
  EXPECT_EQ(players_in(match), 1);
  const auto stale = registry_->leave(1, 100);
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(stale));
  EXPECT_EQ(std::get<DirectoryError>(stale).code, DirectoryErrorCode::NotInMatch);
  EXPECT_EQ(players_in(match), 1);
  EXPECT_TRUE(std::holds_alternative<Done>(registry_->leave(1, 200)));
  EXPECT_EQ(players_in(match), 0);
}

TEST_F(LimitedRegistryTest, MatchCreationIsLimitedPerAccountAndServerWide) {
  const auto create = [&](std::uint64_t account) {
    return registry_->create({.name = "mine", .max_players = 4, .map = "", .creator = account});
  };
  const auto code = [](const DirectoryResult<MatchSummary>& result) {
    return std::holds_alternative<DirectoryError>(result) ? std::get<DirectoryError>(result).code
                                                          : DirectoryErrorCode::InvalidRequest;
  };
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(create(7)));
  EXPECT_EQ(code(create(7)), DirectoryErrorCode::TooManyMatches);  // one open per account
  EXPECT_EQ(registry_->refused(SeatRefusal::AccountMatches), 1u);
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(create(8)));
  EXPECT_EQ(code(create(9)), DirectoryErrorCode::TooManyMatches);  // two created, server-wide
  EXPECT_EQ(registry_->refused(SeatRefusal::CreatedMatches), 1u);
  // The server's own matches do not count against the created ones.
  EXPECT_EQ(registry_->hosts().size(), 2u);
  open("rotation", 4);
  EXPECT_EQ(registry_->hosts().size(), 3u);
}

// A ticket for a new match opens one owned by no account: an account whose placed match filled
// up and that is placed in another new match is not refused TOO_MANY_MATCHES after its ticket
// was used (it did not choose to create either). The server-wide limits still hold.
TEST_F(LimitedRegistryTest, PlacedMatchesAreNoAccountsButCountServerWideAndCloseWhenEmpty) {
  const auto create = [&](std::uint64_t creator) {
    return registry_->create({.name = "m", .max_players = 4, .map = "", .creator = creator});
  };
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(create(7)));  // the account's own, its one
  const auto placed = create(kPlacementCreator);
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(placed));
  const std::uint32_t id = std::get<MatchSummary>(placed).id;
  // Two created matches are open, server-wide: a third placed one waits.
  const auto third = create(kPlacementCreator);
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(third));
  EXPECT_EQ(std::get<DirectoryError>(third).code, DirectoryErrorCode::TooManyMatches);
  EXPECT_EQ(registry_->refused(SeatRefusal::CreatedMatches), 1u);
  EXPECT_EQ(registry_->refused(SeatRefusal::AccountMatches), 0u);
  // Empty for empty_match_close_after_us, it closes like a created match.
  now_ += 60 * proto::kMicrosPerSecond;
  registry_->close_empty_matches();
  EXPECT_FALSE(listed(id));
  // And placement opens more than an account's per-minute creations (2 here).
  for (int i = 0; i < 2; ++i) {
    now_ += 61 * proto::kMicrosPerSecond;
    registry_->close_empty_matches();
    EXPECT_TRUE(std::holds_alternative<MatchSummary>(create(kPlacementCreator))) << i;
    EXPECT_TRUE(std::holds_alternative<MatchSummary>(create(kPlacementCreator))) << i;
  }
  EXPECT_EQ(registry_->refused(SeatRefusal::AccountCreateRate), 0u);
}

SeatLimits two_per_account() {
  SeatLimits limits = tight_limits();
  limits.created_matches_per_account = 2;
  return limits;
}

class CreateRateRegistryTest : public MatchRegistryTest {
 protected:
  CreateRateRegistryTest() : MatchRegistryTest(10 * proto::kMicrosPerSecond, two_per_account()) {}
};

TEST_F(CreateRateRegistryTest, AnAccountCreatesAtItsRate) {
  const auto create = [&](std::uint64_t account) {
    return registry_->create({.name = "mine", .max_players = 4, .map = "", .creator = account});
  };
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(create(7)));
  // Room for a second match of its own, but 2 a minute is one per 30 s.
  const auto fast = create(7);
  ASSERT_TRUE(std::holds_alternative<DirectoryError>(fast));
  EXPECT_EQ(std::get<DirectoryError>(fast).code, DirectoryErrorCode::CreateRateLimited);
  EXPECT_EQ(registry_->refused(SeatRefusal::AccountCreateRate), 1u);
  now_ += 31 * proto::kMicrosPerSecond;
  EXPECT_TRUE(std::holds_alternative<MatchSummary>(create(7)));
}

TEST_F(LimitedRegistryTest, ACreatedMatchClosesWhenEmptyTooLongAndTheRotationStays) {
  const std::uint32_t rotation = open("rotation", 4);
  auto created = registry_->create({.name = "mine", .max_players = 4, .map = "", .creator = 7});
  ASSERT_TRUE(std::holds_alternative<MatchSummary>(created));
  const std::uint32_t mine = std::get<MatchSummary>(created).id;
  ASSERT_TRUE(std::holds_alternative<JoinGrant>(registry_->join(1, "p", mine, from(1))));
  registry_->connected(1, mine);
  now_ += 120 * proto::kMicrosPerSecond;  // seated: it stays however long
  registry_->close_empty_matches();
  EXPECT_TRUE(listed(mine));
  ASSERT_TRUE(std::holds_alternative<Done>(registry_->leave(1, 1)));
  now_ += 59 * proto::kMicrosPerSecond;
  registry_->close_empty_matches();
  EXPECT_TRUE(listed(mine));
  now_ += 1 * proto::kMicrosPerSecond;
  registry_->close_empty_matches();
  EXPECT_FALSE(listed(mine));
  EXPECT_TRUE(listed(rotation));  // empty since it opened, but the server's own
  EXPECT_EQ(registry_->empty_matches_closed(), 1u);
  for (int i = 0; i < 200 && ended_ == 0; ++i) io_.run_for(5ms);
  EXPECT_EQ(ended_, 1);  // handed over like a match that ended
}

}  // namespace
}  // namespace ricochet::server::match_registry_test
