// Placement over both backends (placement.h), on fake time: heartbeats keep a server live for
// the TTL and purge_stale removes it with its matches and tickets; assign fills the fullest open
// match first, counts open tickets as held seats, then makes a new match on the server with the
// most free seats; a ticket is claimed once, by its server and account, before it expires;
// leave; invalid input refused; and processes racing for the last seat on one database.

#include "ricochet/db/placement.h"

#include <sodium.h>
#include <sys/wait.h>
#include <unistd.h>

#include <map>

#include "store_fixture.h"

namespace ricochet::db::test::placement_test {
namespace {

constexpr UnixMillis kTtlMs = 15'000;
constexpr UnixMillis kLifetimeMs = 30'000;
constexpr UnixMillis kT0 = 1'000'000;

GameServerRow server_row(const std::string& id, std::int32_t capacity, std::int32_t players = 0) {
  GameServerRow row;
  row.server_id = id;
  row.host = id + ".example.net";
  row.control_port = 7777;
  row.game_port = 7778;
  row.certificate_sha256 = std::string(64, 'a');
  row.version = "ricochet 1.0";
  row.capacity = capacity;
  row.players = players;
  row.started_ms = kT0 - 60'000;
  row.admin_port = 9100;
  return row;
}

HostedMatch hosted(MatchId id, std::int32_t players, std::int32_t capacity,
                   const std::string& map = "foundry", const std::string& mode = "ffa",
                   bool open = true) {
  return HostedMatch{id, mode, map, players, capacity, open};
}

/// SHA-256 of a token's bytes, as the store keys tickets.
std::string sha256_of_token(const std::string& token) {
  std::string bytes(token.size() / 2, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<char>(std::stoi(token.substr(2 * i, 2), nullptr, 16));
  std::string digest(crypto_hash_sha256_BYTES, '\0');
  crypto_hash_sha256(reinterpret_cast<unsigned char*>(digest.data()),
                     reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  return digest;
}

PlacementOptions options(UnixMillis server_ttl_ms = kTtlMs) {
  PlacementOptions o;
  o.server_ttl_ms = server_ttl_ms;
  o.ticket_lifetime_ms = kLifetimeMs;
  return o;
}

class PlacementTest : public StoreTest {
 protected:
  PlacementTest() : placement_(*store_, options()) {}

  void beat(const GameServerRow& row, const std::vector<HostedMatch>& matches, UnixMillis now) {
    RICOCHET_DB_ASSERT_OK(placement_.heartbeat(row, matches, now));
  }
  std::vector<std::string> live_ids(UnixMillis now) {
    std::vector<std::string> ids;
    for (const GameServerRow& row : must(placement_.live_servers(now), "live_servers"))
      ids.push_back(row.server_id);
    return ids;
  }
  /// Where `account` is assigned at `now`, as "server/match".
  std::string place(AccountId account, UnixMillis now, const std::string& map = "") {
    const Assignment a = must(placement_.assign(account, "ffa", map, now), "assign");
    return a.server_id + "/" + std::to_string(a.match_id);
  }
  std::vector<AccountId> accounts(int n) {
    std::vector<AccountId> ids;
    for (int i = 0; i < n; ++i) ids.push_back(add("player" + std::to_string(i)));
    return ids;
  }

  Placement placement_;
};

// --- the directory ---

TEST_P(PlacementTest, AHeartbeatKeepsAServerLiveForTheTtlAndReplacesItsMatches) {
  beat(server_row("s1", 32, 5), {hosted(1, 3, 16), hosted(2, 2, 16)}, kT0);
  EXPECT_EQ(live_ids(kT0), std::vector<std::string>{"s1"});
  EXPECT_EQ(live_ids(kT0 + kTtlMs - 1), std::vector<std::string>{"s1"});
  EXPECT_TRUE(live_ids(kT0 + kTtlMs).empty());

  const auto listed = must(placement_.live_servers(kT0 + 1), "live_servers");
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].host, "s1.example.net");
  EXPECT_EQ(listed[0].control_port, 7777);
  EXPECT_EQ(listed[0].game_port, 7778);
  EXPECT_EQ(listed[0].certificate_sha256, std::string(64, 'a'));
  EXPECT_EQ(listed[0].version, "ricochet 1.0");
  EXPECT_EQ(listed[0].capacity, 32);
  EXPECT_EQ(listed[0].players, 5);
  EXPECT_EQ(listed[0].heartbeat_ms, kT0);  // the heartbeat's time, not the row's field
  EXPECT_EQ(listed[0].started_ms, kT0 - 60'000);
  EXPECT_EQ(listed[0].admin_port, 9100);
  // The directory: the same rows with their matches; none once the row is past the TTL.
  const FleetDirectory directory = must(placement_.directory(kT0 + 1), "directory");
  ASSERT_EQ(directory.servers.size(), 1u);
  EXPECT_EQ(directory.servers[0].admin_port, 9100);
  ASSERT_EQ(directory.matches.size(), 2u);
  EXPECT_EQ(directory.matches[1].server_id, "s1");
  EXPECT_EQ(directory.matches[1].match.match_id, 2);
  EXPECT_EQ(directory.matches[1].match.players, 2);
  const FleetDirectory gone = must(placement_.directory(kT0 + kTtlMs), "directory");
  EXPECT_TRUE(gone.servers.empty());
  EXPECT_TRUE(gone.matches.empty());

  // The next heartbeat moves the TTL on and replaces the matches wholesale (and the row: this
  // one advertises no admin port).
  GameServerRow unadvertised = server_row("s1", 32, 7);
  unadvertised.admin_port = 0;
  beat(unadvertised, {hosted(3, 7, 16, "arena", "tdm")}, kT0 + 10'000);
  EXPECT_EQ(must(placement_.live_servers(kT0 + 10'001), "live_servers").at(0).admin_port, 0);
  EXPECT_EQ(live_ids(kT0 + kTtlMs), std::vector<std::string>{"s1"});
  EXPECT_EQ(rows("game_servers"), 1);
  EXPECT_EQ(rows("game_server_matches"), 1);
  EXPECT_EQ(raw_integer("SELECT match_id FROM game_server_matches"), 3);
  EXPECT_EQ(raw_integer("SELECT players FROM game_servers"), 7);
}

TEST_P(PlacementTest, PurgeStaleRemovesDeadServersWithTheirMatchesAndTickets) {
  const auto ids = accounts(2);
  beat(server_row("old", 16), {hosted(1, 0, 16)}, kT0);
  beat(server_row("new", 16), {hosted(1, 10, 16)}, kT0 + 10'000);
  EXPECT_EQ(place(ids[0], kT0 + 10'000), "new/1");                 // the fuller match
  beat(server_row("new", 16), {hosted(1, 16, 16)}, kT0 + 10'000);  // now full
  EXPECT_EQ(place(ids[1], kT0 + 10'000), "old/1");

  const Purged purged = must(placement_.purge_stale(kT0 + kTtlMs), "purge_stale");
  EXPECT_EQ(purged.servers, 1);
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM game_servers WHERE server_id = 'old'"), 0);
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM game_server_matches WHERE server_id = 'old'"), 0);
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM tickets WHERE server_id = 'old'"), 0);
  EXPECT_EQ(rows("game_server_matches"), 1);
  EXPECT_EQ(rows("tickets"), 1);  // new's, still open

  // Expired tickets go too, claimed or not.
  const Purged later = must(placement_.purge_stale(kT0 + 10'000 + kLifetimeMs), "purge_stale");
  EXPECT_EQ(later.servers, 1);
  EXPECT_EQ(rows("tickets"), 0);
}

TEST_P(PlacementTest, LeaveDeletesTheRowItsMatchesAndItsUnclaimedTickets) {
  const auto ids = accounts(2);
  beat(server_row("s1", 16), {hosted(1, 0, 16)}, kT0);
  beat(server_row("s2", 16), {hosted(1, 0, 16)}, kT0);
  const Assignment claimed = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  ASSERT_EQ(claimed.server_id, "s1");  // ties go by server id
  ASSERT_TRUE(placement_.claim(claimed.token, "s1", ids[0], kT0 + 1).ok());
  ASSERT_EQ(place(ids[1], kT0 + 2), "s1/1");  // the claimed ticket holds its seat: the fuller

  EXPECT_TRUE(must(placement_.leave("s1"), "leave"));
  EXPECT_FALSE(must(placement_.leave("s1"), "leave again"));
  EXPECT_EQ(live_ids(kT0 + 3), std::vector<std::string>{"s2"});
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM game_server_matches WHERE server_id = 's1'"), 0);
  // The claimed ticket stays until it expires; the unclaimed one is gone.
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM tickets WHERE server_id = 's1'"), 1);
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM tickets WHERE claimed_ms IS NOT NULL"), 1);
  EXPECT_EQ(place(ids[1], kT0 + 4), "s2/1");
}

// --- assignment ---

TEST_P(PlacementTest, PlayersFillTheFullestOpenMatchThenTheNext) {
  const auto ids = accounts(6);
  beat(server_row("a", 64, 29),
       {hosted(1, 12, 16), hosted(2, 2, 16), hosted(3, 15, 16, "foundry", "ffa", false)}, kT0);
  beat(server_row("b", 64, 13), {hosted(7, 13, 16), hosted(8, 0, 16, "arena")}, kT0);
  // b/7 (13 of 16) before a/1 (12); the closed a/3 never. Open tickets count as seated.
  EXPECT_EQ(place(ids[0], kT0), "b/7");  // 14 of 16
  EXPECT_EQ(place(ids[1], kT0), "b/7");  // 15
  EXPECT_EQ(place(ids[2], kT0), "b/7");  // 16: full
  EXPECT_EQ(place(ids[3], kT0), "a/1");
  EXPECT_EQ(place(ids[4], kT0), "a/1");
  // A map asked for: only its matches.
  EXPECT_EQ(place(ids[5], kT0, "arena"), "b/8");
}

TEST_P(PlacementTest, EqualMatchesGoToTheLeastLoadedServer) {
  const auto ids = accounts(1);
  beat(server_row("busy", 32, 30), {hosted(1, 4, 16), hosted(2, 14, 16, "arena")}, kT0);
  beat(server_row("calm", 32, 4), {hosted(5, 4, 16)}, kT0);
  EXPECT_EQ(place(ids[0], kT0, "foundry"), "calm/5");
}

TEST_P(PlacementTest, ANewMatchGoesToTheServerWithTheMostFreeSeats) {
  const auto ids = accounts(3);
  beat(server_row("small", 40, 16), {hosted(1, 16, 16)}, kT0);
  beat(server_row("large", 64, 32), {hosted(1, 16, 16), hosted(2, 16, 16)}, kT0);
  beat(server_row("other", 128, 0), {hosted(1, 0, 16, "arena", "tdm")}, kT0);  // no ffa
  const Assignment a = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  EXPECT_EQ(a.server_id, "large");  // 32 free against 24
  EXPECT_EQ(a.match_id, 0);
  EXPECT_EQ(a.mode, "ffa");
  EXPECT_EQ(a.map, "");
  EXPECT_EQ(a.host, "large.example.net");
  EXPECT_EQ(a.expires_ms, kT0 + kLifetimeMs);
  // The ticket for the new match holds a seat of "large": 31 free, still more than 24.
  EXPECT_EQ(place(ids[1], kT0, "foundry"), "large/0");
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM tickets WHERE match_id = 0 AND map = 'foundry'"), 1);
}

TEST_P(PlacementTest, NoRoomAndUnknownModesAreTheirOwnErrors) {
  const auto ids = accounts(2);
  EXPECT_TRUE(
      fails_with(placement_.assign(ids[0], "ffa", "", kT0), DbErrorCode::NoServerAvailable));
  beat(server_row("full", 16, 16), {hosted(1, 16, 16)}, kT0);
  auto full = placement_.assign(ids[0], "ffa", "", kT0);
  ASSERT_TRUE(fails_with(full, DbErrorCode::NoServerAvailable));
  EXPECT_NE(full.error().message.find("full"), std::string::npos) << full.error().message;
  auto mode = placement_.assign(ids[0], "ctf", "", kT0);
  ASSERT_TRUE(fails_with(mode, DbErrorCode::UnknownModeOrMap));
  EXPECT_NE(mode.error().message.find("'ctf'"), std::string::npos) << mode.error().message;
  EXPECT_TRUE(
      fails_with(placement_.assign(ids[0], "ffa", "arena", kT0), DbErrorCode::UnknownModeOrMap));
  // A server whose heartbeat is older than the TTL is not there.
  beat(server_row("gone", 16, 0), {hosted(1, 0, 16)}, kT0 - kTtlMs);
  EXPECT_TRUE(
      fails_with(placement_.assign(ids[1], "ffa", "", kT0), DbErrorCode::NoServerAvailable));
  EXPECT_EQ(rows("tickets"), 0);
}

TEST_P(PlacementTest, OpenTicketsHoldSeatsUntilClaimedOrExpired) {
  const auto ids = accounts(4);
  beat(server_row("s1", 8), {hosted(1, 0, 2), hosted(2, 0, 4)}, kT0);
  const Assignment first = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  EXPECT_EQ(first.match_id, 1);               // equal (empty) matches: the first by id
  EXPECT_EQ(place(ids[1], kT0 + 1), "s1/1");  // 1 of 2 held: the fullest
  EXPECT_EQ(place(ids[2], kT0 + 2), "s1/2");  // match 1 is held full

  auto held = must(placement_.held_seats("s1", kT0 + 2), "held_seats");
  ASSERT_EQ(held.size(), 2u);
  EXPECT_EQ(held[0].match_id, 1);
  EXPECT_EQ(held[0].seats, 2);
  EXPECT_EQ(held[1].match_id, 2);
  EXPECT_EQ(held[1].seats, 1);
  EXPECT_TRUE(must(placement_.held_seats("s2", kT0 + 2), "held_seats of another").empty());

  // Claimed: still held until a heartbeat counts its player (the next test), and expired:
  // held no more, and the match has room again.
  must(placement_.claim(first.token, "s1", ids[0], kT0 + 3), "claim");
  beat(server_row("s1", 8), {hosted(1, 0, 2), hosted(2, 0, 4)}, kT0 + kLifetimeMs);
  held = must(placement_.held_seats("s1", kT0 + 1 + kLifetimeMs), "held_seats");
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].match_id, 2);
  EXPECT_EQ(place(ids[3], kT0 + 2 + kLifetimeMs), "s1/1");
}

// A burst of tickets: the first is claimed before the server's next heartbeat counts its
// player, and must not give its seat to another ticket meanwhile (on the old rules the claim
// freed it, and the third ticket here went to the full match).
TEST_P(PlacementTest, AClaimedTicketHoldsItsSeatUntilAHeartbeatCountsIt) {
  const auto ids = accounts(3);
  beat(server_row("s1", 8), {hosted(1, 0, 2)}, kT0);
  const Assignment a0 = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  ASSERT_EQ(a0.match_id, 1);
  must(placement_.claim(a0.token, "s1", ids[0], kT0 + 10), "claim");
  const Assignment a1 = must(placement_.assign(ids[1], "ffa", "", kT0 + 11), "assign");
  ASSERT_EQ(a1.match_id, 1);                   // the claimed ticket's seat is one of two
  EXPECT_EQ(place(ids[2], kT0 + 12), "s1/0");  // match 1 is held full: a new match
  auto held = must(placement_.held_seats("s1", kT0 + 12), "held_seats");
  ASSERT_EQ(held.size(), 2u);
  EXPECT_EQ(held[1].match_id, 1);
  EXPECT_EQ(held[1].seats, 2);
  EXPECT_EQ(held[1].claimed, 1);
  EXPECT_EQ(held[0].claimed, 0);

  // A heartbeat whose figures were taken before the claim does not count the player yet.
  GameServerRow before = server_row("s1", 8);
  before.counted_ms = kT0 + 9;
  beat(before, {hosted(1, 0, 2)}, kT0 + 20);
  held = must(placement_.held_seats("s1", kT0 + 20), "held_seats");
  ASSERT_EQ(held.size(), 2u);
  EXPECT_EQ(held[1].seats, 2);

  // One taken as the second claim is made counts the first player only; the second ticket,
  // claimed at the figures' very millisecond, may not be seated in them and still holds.
  must(placement_.claim(a1.token, "s1", ids[1], kT0 + 25), "claim");
  GameServerRow counting = server_row("s1", 8, 1);
  counting.counted_ms = kT0 + 25;
  beat(counting, {hosted(1, 1, 2)}, kT0 + 30);
  held = must(placement_.held_seats("s1", kT0 + 30), "held_seats");
  ASSERT_EQ(held.size(), 2u);
  EXPECT_EQ(held[1].seats, 1);
  EXPECT_EQ(held[1].claimed, 1);

  // Figures from the future are refused: they would release seats not yet counted.
  GameServerRow ahead = server_row("s1", 8, 2);
  ahead.counted_ms = kT0 + 41;
  const DbStatus refused = placement_.heartbeat(ahead, {hosted(1, 2, 2)}, kT0 + 40);
  EXPECT_TRUE(fails_with(refused, DbErrorCode::InvalidPlacement));
  // Counted as of the heartbeat (counted_ms 0): nothing claimed is held any more.
  beat(server_row("s1", 8, 2), {hosted(1, 2, 2)}, kT0 + 40);
  held = must(placement_.held_seats("s1", kT0 + 40), "held_seats");
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].match_id, 0);
}

TEST_P(PlacementTest, AnAccountHoldsOneOpenTicket) {
  const auto ids = accounts(1);
  beat(server_row("s1", 8), {hosted(1, 0, 1)}, kT0);
  const Assignment first = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  // Asking again replaces the ticket: the one seat is not held against the same player.
  const Assignment second = must(placement_.assign(ids[0], "ffa", "", kT0 + 1), "assign again");
  EXPECT_EQ(second.match_id, 1);
  EXPECT_NE(first.token, second.token);
  EXPECT_EQ(rows("tickets"), 1);
  EXPECT_TRUE(
      fails_with(placement_.claim(first.token, "s1", ids[0], kT0 + 2), DbErrorCode::UnknownTicket));
  EXPECT_EQ(must(placement_.claim(second.token, "s1", ids[0], kT0 + 2), "claim").match_id, 1);
}

// --- tickets ---

TEST_P(PlacementTest, ATicketIsStoredAsItsHashAndClaimedOnce) {
  const auto ids = accounts(1);
  beat(server_row("s1", 8), {hosted(4, 1, 8, "arena")}, kT0);
  const Assignment a = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  ASSERT_EQ(a.token.size(), 64u);
  EXPECT_EQ(db_.query_one("SELECT token_hash FROM tickets"), sha256_of_token(a.token));

  const ClaimedTicket claimed = must(placement_.claim(a.token, "s1", ids[0], kT0 + 5), "claim");
  EXPECT_EQ(claimed.match_id, 4);
  EXPECT_EQ(claimed.mode, "ffa");
  EXPECT_EQ(claimed.map, "arena");
  EXPECT_EQ(raw_integer("SELECT claimed_ms FROM tickets"), kT0 + 5);
  auto again = placement_.claim(a.token, "s1", ids[0], kT0 + 6);
  ASSERT_TRUE(fails_with(again, DbErrorCode::UnknownTicket));
  EXPECT_NE(again.error().message.find("already claimed"), std::string::npos)
      << again.error().message;
}

TEST_P(PlacementTest, AClaimNeedsItsServerItsAccountAndTime) {
  const auto ids = accounts(2);
  beat(server_row("s1", 8), {hosted(1, 0, 8)}, kT0);
  const Assignment a = must(placement_.assign(ids[0], "ffa", "", kT0), "assign");
  auto wrong_server = placement_.claim(a.token, "s2", ids[0], kT0 + 1);
  ASSERT_TRUE(fails_with(wrong_server, DbErrorCode::UnknownTicket));
  EXPECT_NE(wrong_server.error().message.find("'s1'"), std::string::npos);
  auto wrong_account = placement_.claim(a.token, "s1", ids[1], kT0 + 1);
  ASSERT_TRUE(fails_with(wrong_account, DbErrorCode::UnknownTicket));
  EXPECT_NE(wrong_account.error().message.find("another account"), std::string::npos);
  EXPECT_TRUE(fails_with(placement_.claim(a.token, "s1", ids[0], a.expires_ms),
                         DbErrorCode::ExpiredTicket));
  EXPECT_TRUE(fails_with(placement_.claim(std::string(64, '0'), "s1", ids[0], kT0 + 1),
                         DbErrorCode::UnknownTicket));
  EXPECT_TRUE(
      fails_with(placement_.claim("abc", "s1", ids[0], kT0 + 1), DbErrorCode::UnknownTicket));
  std::string upper = a.token;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  EXPECT_TRUE(
      fails_with(placement_.claim(upper, "s1", ids[0], kT0 + 1), DbErrorCode::UnknownTicket));
  // None of those took it: the right claim still works, just before it expires.
  EXPECT_EQ(must(placement_.claim(a.token, "s1", ids[0], a.expires_ms - 1), "claim").match_id, 1);
}

// --- what comes from outside ---

TEST_P(PlacementTest, InvalidRowsAndRequestsAreRefusedWithTheField) {
  const auto ids = accounts(1);
  const std::vector<std::pair<std::string, GameServerRow>> bad_rows = [] {
    std::vector<std::pair<std::string, GameServerRow>> out;
    auto with = [&](const std::string& field, auto change) {
      GameServerRow row = server_row("s1", 16);
      change(row);
      out.emplace_back(field, row);
    };
    with("server_id", [](GameServerRow& r) { r.server_id = ""; });
    with("server_id", [](GameServerRow& r) { r.server_id = "a b"; });
    with("server_id", [](GameServerRow& r) { r.server_id = std::string(65, 'x'); });
    with("host", [](GameServerRow& r) { r.host = ""; });
    with("host", [](GameServerRow& r) { r.host = "evil host"; });
    with("host", [](GameServerRow& r) { r.host = std::string(254, 'h'); });
    with("control_port", [](GameServerRow& r) { r.control_port = 0; });
    with("game_port", [](GameServerRow& r) { r.game_port = 65536; });
    with("admin_port", [](GameServerRow& r) { r.admin_port = -1; });
    with("admin_port", [](GameServerRow& r) { r.admin_port = 65536; });
    with("certificate_sha256", [](GameServerRow& r) { r.certificate_sha256 = "abc"; });
    with("certificate_sha256",
         [](GameServerRow& r) { r.certificate_sha256 = std::string(64, 'G'); });
    with("version", [](GameServerRow& r) { r.version = std::string(65, 'v'); });
    with("version", [](GameServerRow& r) { r.version = std::string("1.0\n", 4); });
    with("capacity", [](GameServerRow& r) { r.capacity = 0; });
    with("players", [](GameServerRow& r) { r.players = 17; });
    with("players", [](GameServerRow& r) { r.players = -1; });
    return out;
  }();
  for (const auto& [field, row] : bad_rows) {
    const DbStatus s = placement_.heartbeat(row, {}, kT0);
    ASSERT_TRUE(fails_with(s, DbErrorCode::InvalidPlacement)) << field;
    EXPECT_NE(s.error().message.find(field), std::string::npos) << s.error().message;
  }
  const std::vector<std::pair<std::string, std::vector<HostedMatch>>> bad_matches = {
      {"match_id", {hosted(0, 0, 16)}},
      {"listed twice", {hosted(1, 0, 16), hosted(1, 0, 16)}},
      {"mode", {hosted(1, 0, 16, "foundry", "FFA")}},
      {"mode", {hosted(1, 0, 16, "foundry", "")}},
      {"map", {hosted(1, 0, 16, "a map")}},
      {"map", {hosted(1, 0, 16, std::string(65, 'm'))}},
      {"capacity", {hosted(1, 0, 0)}},
      {"players", {hosted(1, 17, 16)}},
  };
  for (const auto& [field, matches] : bad_matches) {
    const DbStatus s = placement_.heartbeat(server_row("s1", 16), matches, kT0);
    ASSERT_TRUE(fails_with(s, DbErrorCode::InvalidPlacement)) << field;
    EXPECT_NE(s.error().message.find(field), std::string::npos) << s.error().message;
  }
  EXPECT_EQ(rows("game_servers"), 0);
  EXPECT_EQ(placement_.refusals().count(DbErrorCode::InvalidPlacement),
            bad_rows.size() + bad_matches.size());

  EXPECT_TRUE(fails_with(placement_.assign(ids[0], "", "", kT0), DbErrorCode::InvalidPlacement));
  EXPECT_TRUE(fails_with(placement_.assign(ids[0], std::string(33, 'f'), "", kT0),
                         DbErrorCode::InvalidPlacement));
  EXPECT_TRUE(
      fails_with(placement_.assign(ids[0], "ffa", "x\x01y", kT0), DbErrorCode::InvalidPlacement));
  EXPECT_TRUE(fails_with(placement_.assign(0, "ffa", "", kT0), DbErrorCode::InvalidPlacement));
  EXPECT_TRUE(fails_with(placement_.leave("a;b"), DbErrorCode::InvalidPlacement));
  EXPECT_TRUE(fails_with(placement_.held_seats("", kT0), DbErrorCode::InvalidPlacement));
  EXPECT_TRUE(fails_with(placement_.claim(std::string(64, '0'), std::string(1, '\0'), ids[0], kT0),
                         DbErrorCode::InvalidPlacement));

  Placement misconfigured(*store_, options(0));
  const auto live = misconfigured.live_servers(kT0);
  ASSERT_TRUE(fails_with(live, DbErrorCode::InvalidPlacement));
  EXPECT_NE(live.error().message.find("server_ttl_ms"), std::string::npos) << live.error().message;
}

TEST_P(PlacementTest, AnUnknownAccountGetsNoTicket) {
  beat(server_row("s1", 8), {hosted(1, 0, 8)}, kT0);
  EXPECT_TRUE(fails_with(placement_.assign(12345, "ffa", "", kT0), DbErrorCode::UnknownAccount));
  EXPECT_EQ(rows("tickets"), 0);
}

// --- several servers on one database ---

constexpr int kRacers = 3;
constexpr int kRounds = 40;

/// The body of a racer process. Each round, once `start` gives it a byte (all racers at once),
/// it asks for a seat in the round's mode, hosted on a server of one seat (so no new match can
/// be made either), for accounts[round] (one open ticket per account: its next round must not
/// drop the seat it won), and writes one byte to `out`: 'y' got it, 'n' NoServerAvailable, 'e'
/// anything else. Exits 0 unless it could not run.
int race(const std::string& url, const std::vector<AccountId>& accounts, int start, int out) {
  auto store = open_store({.url_or_path = url, .busy_timeout_ms = 30'000});
  if (!store.ok()) return 2;
  Placement placement(*store.value(), options());
  for (int r = 0; r < kRounds; ++r) {
    char go = 0;
    if (read(start, &go, 1) != 1) return 3;
    auto a =
        placement.assign(accounts[static_cast<std::size_t>(r)], "m" + std::to_string(r), "", kT0);
    const char result =
        a.ok() ? 'y' : (a.error().code == DbErrorCode::NoServerAvailable ? 'n' : 'e');
    if (write(out, &result, 1) != 1) return 4;
  }
  return 0;
}

TEST_P(PlacementTest, ProcessesRacingForTheLastSeatGetItOnce) {
  const auto ids = accounts(kRacers * kRounds);
  for (int r = 0; r < kRounds; ++r) {
    const std::string n = std::to_string(r);
    beat(server_row("s" + n, 1), {hosted(1, 0, 1, "foundry", "m" + n)}, kT0);
  }

  // Closed before fork: a connection must never cross one (SQLite's file locks are per process).
  store_.reset();
  int results[2];
  ASSERT_EQ(pipe(results), 0);
  std::vector<pid_t> racers;
  std::vector<int> starts;  // the write end of each racer's start pipe
  for (int i = 0; i < kRacers; ++i) {
    int start[2];
    ASSERT_EQ(pipe(start), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {  // no gtest in the child
      const auto first = ids.begin() + i * kRounds;
      _exit(race(db_.url_or_path(), {first, first + kRounds}, start[0], results[1]));
    }
    close(start[0]);
    racers.push_back(pid);
    starts.push_back(start[1]);
  }
  close(results[1]);
  std::map<char, int> outcomes;
  std::vector<int> winners;  // per round
  for (int r = 0; r < kRounds; ++r) {
    for (const int start : starts) ASSERT_EQ(write(start, "g", 1), 1);
    int won = 0;
    for (int i = 0; i < kRacers; ++i) {
      char c = 0;
      ASSERT_EQ(read(results[0], &c, 1), 1) << "a racer stopped in round " << r;
      ++outcomes[c];
      won += c == 'y' ? 1 : 0;
    }
    winners.push_back(won);
  }
  for (const int start : starts) close(start);
  close(results[0]);
  for (pid_t pid : racers) {
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "racer status " << status;
  }
  // Every round's one seat went to exactly one racer; the others were told there is no room.
  EXPECT_EQ(winners, std::vector<int>(kRounds, 1));
  EXPECT_EQ(outcomes['n'], kRounds * (kRacers - 1));
  EXPECT_EQ(outcomes['e'], 0);
  EXPECT_EQ(rows("tickets"), kRounds);
}

INSTANTIATE_TEST_SUITE_P(Backends, PlacementTest, kBackends, backend_name);

}  // namespace
}  // namespace ricochet::db::test::placement_test
