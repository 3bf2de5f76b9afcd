// The match side of the control channel through a fake directory: list, create, join (the
// connect token and keys), chat, leave, match results pushed by the server, the state table
// enforced on each, and a resumed connection back in its match.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <vector>

#include "control_test_client.h"
#include "ricochet/proto/chat_text.h"

namespace ricochet::server::test::control_matches_test {
namespace {

wire::ClientMessage create(const std::string& name, std::uint32_t max_players) {
  wire::ClientMessage m;
  m.mutable_create_match()->set_name(name);
  m.mutable_create_match()->set_max_players(max_players);
  return m;
}

TEST(ControlMatches, ListCreateAndListAgain) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  auto reply = client.request(ControlTestClient::list_matches());
  ASSERT_EQ(reply.list_matches().matches_size(), 1);
  EXPECT_EQ(reply.list_matches().matches(0).name(), "arena 1");
  EXPECT_EQ(reply.list_matches().matches(0).max_players(), 16u);

  reply = client.request(create("duel", 2));
  ASSERT_TRUE(reply.has_create_match()) << reply.DebugString();
  EXPECT_EQ(reply.create_match().match().match_id(), 2u);
  EXPECT_EQ(reply.create_match().match().max_players(), 2u);
  EXPECT_EQ(client.request(ControlTestClient::list_matches()).list_matches().matches_size(), 2);
}

TEST(ControlMatches, CreateOutOfRangeIsTheDirectorysError) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  const auto reply = client.request(create("huge", 4'000'000'000u));
  EXPECT_EQ(reply.error().code(), wire::INVALID_REQUEST) << reply.DebugString();
  EXPECT_NE(reply.error().message().find("max_players"), std::string::npos);
}

TEST(ControlMatches, JoinHandsOverTheTokenAndKeys) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  const auto reply = client.request(ControlTestClient::join(1));
  ASSERT_TRUE(reply.has_join_match()) << reply.DebugString();
  const wire::JoinMatchReply& join = reply.join_match();
  EXPECT_EQ(join.match_id(), 1u);
  EXPECT_EQ(join.udp_port(), 7778u);
  EXPECT_EQ(join.connect_token(), std::string(64, '\xab'));
  EXPECT_EQ(join.client_to_server_key(), std::string(32, '\x01'));
  EXPECT_EQ(join.server_to_client_key(), std::string(32, '\x02'));
  EXPECT_GT(join.token_expires_in_ms(), 29'000u);
  EXPECT_LE(join.token_expires_in_ms(), 30'000u);
  EXPECT_EQ(join.timeout_s(), 5u);
  EXPECT_EQ(rig.directory().joined_names, (std::vector<std::string>{"ada"}));
}

TEST(ControlMatches, JoinAnUnknownMatchIsNotFoundAndStaysAuthenticated) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  auto reply = client.request(ControlTestClient::join(99));
  EXPECT_EQ(reply.error().code(), wire::MATCH_NOT_FOUND);
  reply = client.request(ControlTestClient::chat("hello"));  // not in a match
  EXPECT_EQ(reply.error().code(), wire::WRONG_STATE);
}

TEST(ControlMatches, ChatInAMatchReachesTheDirectoryThenLeave) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  ASSERT_TRUE(client.request(ControlTestClient::join(1)).has_join_match());
  EXPECT_TRUE(client.request(ControlTestClient::chat("gl hf")).has_chat());
  EXPECT_EQ(rig.directory().chats_seen(), (std::vector<std::string>{"gl hf"}));

  auto reply = client.request(ControlTestClient::chat(""));
  EXPECT_EQ(reply.error().code(), wire::INVALID_REQUEST);
  // One limit with the match's (proto::kMaxChatBytes): over it the sender is told, not the match.
  reply = client.request(ControlTestClient::chat(std::string(proto::kMaxChatBytes + 1, 'x')));
  EXPECT_EQ(reply.error().code(), wire::INVALID_REQUEST);
  EXPECT_NE(reply.error().message().find("got 201"), std::string::npos) << reply.error().message();
  EXPECT_TRUE(
      client.request(ControlTestClient::chat(std::string(proto::kMaxChatBytes, 'x'))).has_chat());
  // A right-to-left override would make the line read backwards on everyone's screen.
  reply =
      client.request(ControlTestClient::chat("gg \xE2\x80\xAE"
                                             "ez"));
  EXPECT_EQ(reply.error().code(), wire::INVALID_REQUEST);
  EXPECT_NE(reply.error().message().find("U+202E"), std::string::npos) << reply.error().message();
  EXPECT_EQ(rig.directory().chats_seen(),
            (std::vector<std::string>{"gl hf", std::string(proto::kMaxChatBytes, 'x')}));
  EXPECT_EQ(rig.refusals(ControlRefusal::InvalidRequest), 3u);

  EXPECT_TRUE(client.request(ControlTestClient::leave()).has_leave_match());
  reply = client.request(ControlTestClient::chat("anyone?"));
  EXPECT_EQ(reply.error().code(), wire::WRONG_STATE);
  reply = client.request(ControlTestClient::leave());
  EXPECT_EQ(reply.error().code(), wire::WRONG_STATE);
}

TEST(ControlMatches, EveryMatchRequestBeforeLoginIsWrongStateAndCounted) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  const std::vector<wire::ClientMessage> requests = {
      ControlTestClient::list_matches(), create("x", 2), ControlTestClient::join(1),
      ControlTestClient::leave(), ControlTestClient::chat("hi")};
  for (const auto& request : requests) {
    const auto reply = client.request(request);
    EXPECT_EQ(reply.error().code(), wire::WRONG_STATE) << request.DebugString();
    EXPECT_NE(reply.error().message().find("allowed: register, login, resume, ping"),
              std::string::npos)
        << reply.error().message();
  }
  EXPECT_EQ(rig.refusals(ControlRefusal::WrongState), requests.size());
  // The client end refused each one too (the rig sent them around it).
  EXPECT_EQ(client.protocol()
                .counters()
                .refused_requests[static_cast<std::size_t>(proto::RequestRefusal::WrongState)],
            requests.size());
  // The connection is still usable.
  EXPECT_TRUE(client.request(ControlTestClient::ping(1)).has_pong());
  EXPECT_TRUE(rig.directory().joined_names.empty());
}

TEST(ControlMatches, RegisterAfterLoginIsWrongState) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  const auto reply = client.request(ControlTestClient::register_account("bob", "password-bob"));
  EXPECT_EQ(reply.error().code(), wire::WRONG_STATE);
}

TEST(ControlMatches, MatchResultsReachThePlayerAndEndInMatch) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  const wire::SessionReply session = client.sign_in("ada");
  ASSERT_TRUE(client.request(ControlTestClient::join(1)).has_join_match());

  wire::ServerMessage results;
  wire::MatchResults& sent = *results.mutable_match_results();
  sent.set_match_id(1);
  sent.set_mode("tdm");
  sent.set_end_reason(wire::MATCH_END_REASON_FRAG_LIMIT);
  wire::TeamScore* red = sent.add_team_scores();
  red->set_team(wire::TEAM_RED);
  red->set_score(20);
  auto* player = sent.add_players();
  player->set_account_id(session.account_id());
  player->set_score(12);
  player->set_team(wire::TEAM_RED);
  player->set_shots(40);
  player->set_hits(15);
  player->set_damage_dealt(300);
  player->set_damage_taken(120);
  player->set_seconds_played(95.5);
  player->set_rank(3);
  rig.server().send_to_account(session.account_id(), results);
  rig.server().send_to_account(session.account_id() + 1, results);  // nobody: dropped

  const auto pushed = client.receive();
  ASSERT_TRUE(pushed && pushed->has_match_results());
  EXPECT_EQ(pushed->request_id(), 0u);
  EXPECT_EQ(pushed->match_results().SerializeAsString(), sent.SerializeAsString());
  EXPECT_EQ(pushed->match_results().players(0).score(), 12);
  // Back to Authenticated on both ends: chat is out of state, joining again is allowed.
  EXPECT_EQ(client.protocol().state(), proto::ControlState::Authenticated);
  EXPECT_EQ(client.request(ControlTestClient::chat("gg")).error().code(), wire::WRONG_STATE);
  EXPECT_TRUE(client.request(ControlTestClient::join(1)).has_join_match());
}

// A phone's TCP connection drops while its game connection plays on: the resumed connection
// is back in the match (PROTOCOL.md, resume, "Back in the match"); before, it was only signed
// in, so its leave and chat were refused and a join moved the seat, kicking the game connection.
TEST(ControlMatches, AResumedConnectionIsBackInItsMatchAndLeaves) {
  ControlRig rig;
  ControlTestClient lost(rig.port());
  ASSERT_TRUE(lost.connect());
  const wire::SessionReply session = lost.sign_in("ada");
  ASSERT_TRUE(lost.request(ControlTestClient::join(1)).has_join_match());

  ControlTestClient resumed(rig.port());
  ASSERT_TRUE(resumed.connect());
  const auto reply = resumed.request(ControlTestClient::resume(session.session_token()));
  ASSERT_TRUE(reply.has_session()) << reply.DebugString();
  EXPECT_EQ(reply.session().match_id(), 1u);
  EXPECT_EQ(resumed.protocol().state(), proto::ControlState::InMatch);
  // It plays the seat now (the server's state table lets chat through, the directory the
  // session); the older connection, never seen to end, no longer speaks for the account.
  EXPECT_TRUE(resumed.request(ControlTestClient::chat("back")).has_chat());
  EXPECT_EQ(rig.directory().chats_seen(), (std::vector<std::string>{"back"}));
  EXPECT_EQ(lost.request(ControlTestClient::chat("ghost")).error().code(), wire::NOT_IN_MATCH);
  EXPECT_EQ(rig.directory().joined_names.size(), 1u) << "no join: the seat was taken back";

  EXPECT_TRUE(resumed.request(ControlTestClient::leave()).has_leave_match());
  EXPECT_FALSE(rig.directory().seated(session.account_id()));
  EXPECT_EQ(resumed.protocol().state(), proto::ControlState::Authenticated);
  EXPECT_EQ(resumed.request(ControlTestClient::chat("anyone?")).error().code(), wire::WRONG_STATE);
}

TEST(ControlMatches, MatchResultsReachTheResumedConnection) {
  ControlRig rig;
  wire::SessionReply session;
  {
    ControlTestClient lost(rig.port());
    ASSERT_TRUE(lost.connect());
    session = lost.sign_in("ada");
    ASSERT_TRUE(lost.request(ControlTestClient::join(1)).has_join_match());
  }
  ControlTestClient resumed(rig.port());
  ASSERT_TRUE(resumed.connect());
  ASSERT_EQ(
      resumed.request(ControlTestClient::resume(session.session_token())).session().match_id(), 1u);
  wire::ServerMessage results;
  results.mutable_match_results()->set_match_id(1);
  results.mutable_match_results()->set_end_reason(wire::MATCH_END_REASON_TIME_LIMIT);
  rig.server().send_to_account(session.account_id(), results);
  const auto pushed = resumed.receive();
  ASSERT_TRUE(pushed && pushed->has_match_results());
  EXPECT_EQ(pushed->match_results().match_id(), 1u);
  EXPECT_EQ(resumed.protocol().state(), proto::ControlState::Authenticated);
  EXPECT_EQ(resumed.request(ControlTestClient::leave()).error().code(), wire::WRONG_STATE);
}

TEST(ControlMatches, AResumeWithoutAHeldSeatIsOnlySignedIn) {
  ControlRig rig;
  ControlTestClient first(rig.port());
  ASSERT_TRUE(first.connect());
  const wire::SessionReply session = first.sign_in("ada");
  ASSERT_TRUE(first.request(ControlTestClient::join(1)).has_join_match());
  ASSERT_TRUE(first.request(ControlTestClient::leave()).has_leave_match());

  ControlTestClient resumed(rig.port());
  ASSERT_TRUE(resumed.connect());
  const auto reply = resumed.request(ControlTestClient::resume(session.session_token()));
  ASSERT_TRUE(reply.has_session()) << reply.DebugString();
  EXPECT_EQ(reply.session().match_id(), 0u);
  EXPECT_EQ(resumed.protocol().state(), proto::ControlState::Authenticated);
  EXPECT_EQ(resumed.request(ControlTestClient::chat("hi")).error().code(), wire::WRONG_STATE);
}

// Issue 29's rule holds: one connection plays an account, and only the sign-in that joined gets
// the seat back by resuming. Another login's token (another device) is only signed in.
TEST(ControlMatches, AResumeOfAnotherSignInDoesNotTakeTheSeatOver) {
  ControlRig rig;
  ControlTestClient player(rig.port());
  ASSERT_TRUE(player.connect());
  player.sign_in("ada");
  ASSERT_TRUE(player.request(ControlTestClient::join(1)).has_join_match());

  ControlTestClient other_device(rig.port());
  ASSERT_TRUE(other_device.connect());
  const wire::SessionReply other = other_device.sign_in("ada", false);
  ControlTestClient resumed(rig.port());
  ASSERT_TRUE(resumed.connect());
  const auto reply = resumed.request(ControlTestClient::resume(other.session_token()));
  ASSERT_TRUE(reply.has_session()) << reply.DebugString();
  EXPECT_EQ(reply.session().match_id(), 0u);
  EXPECT_EQ(resumed.protocol().state(), proto::ControlState::Authenticated);
  // The player's connection still plays the seat.
  EXPECT_TRUE(player.request(ControlTestClient::chat("still here")).has_chat());
  EXPECT_TRUE(player.request(ControlTestClient::leave()).has_leave_match());
}

}  // namespace
}  // namespace ricochet::server::test::control_matches_test

namespace ricochet::server::test::control_matches_test {
namespace {

wire::ClientMessage find(const std::string& mode) {
  wire::ClientMessage m;
  m.mutable_find_match()->set_mode(mode);
  return m;
}

/// Writes the rig's server row (rs-test, 100 seats, `players` seated) with `hosted` into the
/// directory, through its DB worker, at the wall clock's time.
db::DbStatus list_in_directory(ControlRig& rig, std::int32_t players,
                               const std::vector<db::HostedMatch>& hosted) {
  const db::GameServerRow row{.server_id = "rs-test",
                              .host = "127.0.0.1",
                              .control_port = rig.port(),
                              .game_port = 7778,
                              .certificate_sha256 = std::string(64, 'a'),
                              .version = "test",
                              .capacity = 100,
                              .players = players};
  std::promise<db::DbStatus> written;
  rig.db().submit(
      [&](db::DbServices& services) {
        return services.placement.heartbeat(row, hosted,
                                            std::chrono::duration_cast<std::chrono::milliseconds>(
                                                std::chrono::system_clock::now().time_since_epoch())
                                                .count());
      },
      [](std::function<void()> completion) { completion(); },
      [&](db::DbStatus status) { written.set_value(std::move(status)); });
  return written.get_future().get();
}

TEST(ControlPlacement, FindMatchIsLimitedPerAccountAcrossItsConnectionsOnTheServersClock) {
  std::atomic<proto::TimeUs> now{1'000 * proto::kMicrosPerSecond};
  PlacementCounters counters;
  FleetPlacement placement{"rs-test", FindMatchLimiter(30), counters, 16, {}};
  ControlRig rig(
      {}, [&now] { return now.load(); }, {}, nullptr, &placement);
  ControlTestClient first(rig.port());
  ControlTestClient second(rig.port());
  ControlTestClient other(rig.port());
  ASSERT_TRUE(first.connect() && second.connect() && other.connect());
  first.sign_in("seeker");
  second.sign_in("seeker", false);
  other.sign_in("other");
  // No server in the directory: every find_match the limit lets through is answered so.
  for (int i = 0; i < 5; ++i) {
    ControlTestClient& client = i % 2 ? second : first;
    EXPECT_EQ(client.request(find("ffa")).error().code(), wire::NO_SERVER_AVAILABLE) << i;
  }
  const wire::ServerMessage limited = second.request(find("ffa"));
  EXPECT_EQ(limited.error().code(), wire::FIND_MATCH_RATE_LIMITED) << limited.DebugString();
  EXPECT_EQ(other.request(find("ffa")).error().code(), wire::NO_SERVER_AVAILABLE);
  now += 2 * proto::kMicrosPerSecond;  // one more at 30 a minute
  EXPECT_EQ(first.request(find("ffa")).error().code(), wire::NO_SERVER_AVAILABLE);
  EXPECT_EQ(first.request(find("ffa")).error().code(), wire::FIND_MATCH_RATE_LIMITED);
  EXPECT_EQ(counters.tickets[static_cast<std::size_t>(TicketResult::RateLimited)].load(), 2u);
  EXPECT_EQ(counters.tickets[static_cast<std::size_t>(TicketResult::NoServerAvailable)].load(), 7u);
  // A ticket that is not 32 bytes is refused before the database.
  wire::ClientMessage join;
  join.mutable_join_match()->set_ticket("not a ticket");
  EXPECT_EQ(first.request(join).error().code(), wire::UNKNOWN_TICKET);
}

TEST(ControlPlacement, ATicketForANewMatchJoinsAnOpenMatchOfItsModeHereOnce) {
  PlacementCounters counters;
  FleetPlacement placement{"rs-test", FindMatchLimiter(30), counters, 16, {}};
  ControlRig rig({}, {}, {}, nullptr, &placement);
  // The directory: this server, its one ffa match full, so the assignment is a new match here.
  ASSERT_TRUE(list_in_directory(rig, 4,
                                {{.match_id = 9,
                                  .mode = "ffa",
                                  .map = "arena",
                                  .players = 4,
                                  .capacity = 4,
                                  .open = true}})
                  .ok());

  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("newcomer");
  const wire::ServerMessage found = client.request(find("ffa"));
  ASSERT_TRUE(found.has_find_match()) << found.DebugString();
  const wire::Assignment& assignment = found.find_match().assignment();
  EXPECT_EQ(assignment.match_id(), 0u);
  EXPECT_TRUE(assignment.on_this_server());
  EXPECT_EQ(assignment.connection(), "127.0.0.1:" + std::to_string(rig.port()));
  EXPECT_EQ(assignment.certificate_sha256(), std::string(64, 'a'));
  EXPECT_EQ(counters.tickets[static_cast<std::size_t>(TicketResult::Assigned)].load(), 1u);
  wire::ClientMessage join;
  join.mutable_join_match()->set_ticket(assignment.ticket());
  join.mutable_join_match()->set_match_id(77);  // ignored: the ticket names the match
  const wire::ServerMessage joined = client.request(join);
  ASSERT_TRUE(joined.has_join_match()) << joined.DebugString();
  EXPECT_EQ(joined.join_match().match_id(), 1u);  // the fake directory's open ffa match
  EXPECT_EQ(client.state(), proto::ControlState::InMatch);
  EXPECT_EQ(client.request(join).error().code(), wire::UNKNOWN_TICKET);
}

// The directory lists a match until the server's next heartbeat: a ticket for one that ended
// meanwhile seats its player in an open match of its mode and map here (before: MATCH_NOT_FOUND,
// and the client had to find a match again with its ticket spent).
TEST(ControlPlacement, ATicketForAMatchThatEndedJoinsAnotherOfItsModeAndMapHere) {
  PlacementCounters counters;
  FleetPlacement placement{"rs-test", FindMatchLimiter(30), counters, 16, {}};
  ControlRig rig({}, {}, {}, nullptr, &placement);
  // The directory still lists match 5, open; this server (the fake) hosts only match 1.
  ASSERT_TRUE(list_in_directory(rig, 3,
                                {{.match_id = 5,
                                  .mode = "ffa",
                                  .map = "arena",
                                  .players = 3,
                                  .capacity = 4,
                                  .open = true}})
                  .ok());

  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("latecomer");
  const wire::ServerMessage found = client.request(find("ffa"));
  ASSERT_TRUE(found.has_find_match()) << found.DebugString();
  ASSERT_EQ(found.find_match().assignment().match_id(), 5u);
  wire::ClientMessage join;
  join.mutable_join_match()->set_ticket(found.find_match().assignment().ticket());
  const wire::ServerMessage joined = client.request(join);
  ASSERT_TRUE(joined.has_join_match()) << joined.DebugString();
  EXPECT_EQ(joined.join_match().match_id(), 1u);  // the fake's open ffa match on the arena
  EXPECT_TRUE(rig.directory().created.empty());
}

TEST(ControlPlacement, ATicketForANewMatchOpensOneOfTheServersSizeAsPlacementsAndTellsAgones) {
  PlacementCounters counters;
  std::atomic<int> placed{0};
  FleetPlacement placement{"rs-test", FindMatchLimiter(30), counters, 6, [&placed] { ++placed; }};
  ControlRig rig({}, {}, {}, nullptr, &placement);
  rig.directory().set_players(1, 16);  // the fake's one ffa match is full
  ASSERT_TRUE(list_in_directory(rig, 16,
                                {{.match_id = 1,
                                  .mode = "ffa",
                                  .map = "arena",
                                  .players = 16,
                                  .capacity = 16,
                                  .open = true}})
                  .ok());

  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("placedfirst");
  const wire::ServerMessage found = client.request(find("ffa"));
  ASSERT_TRUE(found.has_find_match()) << found.DebugString();
  EXPECT_EQ(found.find_match().assignment().match_id(), 0u);
  // A join without a ticket tells Agones nothing: its player allocates once seated.
  ASSERT_TRUE(client.request(ControlTestClient::join(1)).has_join_match());
  EXPECT_EQ(placed.load(), 0);
  ASSERT_TRUE(client.request(ControlTestClient::leave()).has_leave_match());
  wire::ClientMessage join_placed;
  join_placed.mutable_join_match()->set_ticket(found.find_match().assignment().ticket());
  const wire::ServerMessage joined = client.request(join_placed);
  ASSERT_TRUE(joined.has_join_match()) << joined.DebugString();
  EXPECT_EQ(joined.join_match().match_id(), 2u);
  const auto created = rig.directory().created;
  ASSERT_EQ(created.size(), 1u);
  EXPECT_EQ(created[0].max_players, 6);  // [matches] max_players, not CreateMatchRequest's 16
  EXPECT_EQ(created[0].creator, kPlacementCreator);  // not the account's: no per-account limit
  EXPECT_EQ(placed.load(), 1);
}

TEST(ControlPlacement, WithPlacementOffFindMatchAndTicketsAreRefused) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("alone");
  EXPECT_EQ(client.request(find("ffa")).error().code(), wire::NO_SERVER_AVAILABLE);
  wire::ClientMessage join;
  join.mutable_join_match()->set_ticket(std::string(32, 'x'));
  EXPECT_EQ(client.request(join).error().code(), wire::UNKNOWN_TICKET);
  EXPECT_EQ(client.state(), proto::ControlState::Authenticated);
}

}  // namespace
}  // namespace ricochet::server::test::control_matches_test
