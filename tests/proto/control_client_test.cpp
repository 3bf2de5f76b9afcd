// The control channel's client end on fake time and in-memory bytes: requests numbered and
// framed, the state table enforced before anything is sent, replies matched to their requests in
// any order and moving the state, MatchResults pushed by the server, request timeouts and
// keep-alive pings, and the server's bytes refused (oversize, empty, malformed, no body, unknown
// or wrong replies) with a reason and a counter. Bytes split at every boundary give the same
// events.

#include "ricochet/proto/control_client.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "control_requests.h"

namespace ricochet::proto::control_client_test {
namespace {

constexpr TimeUs kSecond = kMicrosPerSecond;
using test::request_of;

// --- what the client sends ---

/// Every frame the client queued since the last call, parsed.
std::vector<wire::ClientMessage> sent(ControlClient& client) {
  std::vector<std::uint8_t> bytes;
  std::vector<wire::ClientMessage> out;
  if (!client.poll_transmit(bytes)) return out;
  FrameReader reader;
  reader.feed(bytes);
  std::vector<std::uint8_t> payload;
  while (reader.next(payload) == FrameReader::Status::Frame) {
    wire::ClientMessage message;
    EXPECT_EQ(parse_client_message(payload, message), std::nullopt);
    out.push_back(message);
  }
  EXPECT_FALSE(reader.inside_frame());
  return out;
}

std::vector<ControlEvent> events(ControlClient& client) {
  std::vector<ControlEvent> out;
  ControlEvent event;
  while (client.poll_event(event)) out.push_back(std::move(event));
  return out;
}

// --- what the server sends ---

std::vector<std::uint8_t> frame(const wire::ServerMessage& message) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(append_frame(message, bytes));
  return bytes;
}

wire::ServerMessage session(std::uint32_t request_id) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  m.mutable_session()->set_account_id(7);
  m.mutable_session()->set_username("ada");
  m.mutable_session()->set_session_token(std::string(64, 'f'));
  return m;
}

wire::ServerMessage error(std::uint32_t request_id, wire::ErrorCode code) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  m.mutable_error()->set_code(code);
  m.mutable_error()->set_message("what was expected and what came");
  return m;
}

wire::ServerMessage pong(std::uint32_t request_id) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  m.mutable_pong()->set_client_time_us(42);
  return m;
}

wire::ServerMessage list(std::uint32_t request_id) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  m.mutable_list_matches()->add_matches()->set_match_id(1);
  return m;
}

wire::ServerMessage joined(std::uint32_t request_id, std::uint32_t match_id) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  m.mutable_join_match()->set_match_id(match_id);
  return m;
}

wire::ServerMessage left(std::uint32_t request_id) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  m.mutable_leave_match();
  return m;
}

wire::ServerMessage results(std::uint32_t match_id) {
  wire::ServerMessage m;
  m.mutable_match_results()->set_match_id(match_id);
  m.mutable_match_results()->set_mode("ffa");
  m.mutable_match_results()->add_players()->set_account_id(7);
  return m;
}

std::vector<std::uint8_t> header(std::uint32_t length) {
  return {static_cast<std::uint8_t>(length >> 24), static_cast<std::uint8_t>(length >> 16),
          static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length)};
}

// --- driving a client ---

/// A request that must be queued; returns its id.
std::uint32_t ask(ControlClient& client, ClientMessageKind kind, TimeUs now = 0) {
  const RequestResult result = client.request(request_of(kind), now);
  EXPECT_TRUE(result) << name(kind) << " refused: " << name(*result.refusal);
  return result.request_id;
}

/// The reply event the client made of the last frame, or a test failure.
ControlReply reply_event(ControlClient& client) {
  const auto all = events(client);
  EXPECT_EQ(all.size(), 1u);
  if (all.size() != 1 || !std::holds_alternative<ControlReply>(all[0])) {
    ADD_FAILURE() << "expected one reply event";
    return {};
  }
  return std::get<ControlReply>(all[0]);
}

ControlClosed closed_event(ControlClient& client) {
  const auto all = events(client);
  if (all.empty() || !std::holds_alternative<ControlClosed>(all.back())) {
    ADD_FAILURE() << "expected the client to close";
    return {};
  }
  return std::get<ControlClosed>(all.back());
}

/// A client taken to `state` through real replies (Closed: by close()).
ControlClient client_in(ControlState state, ControlClientConfig config = {}) {
  ControlClient client(0, std::move(config));
  if (state == ControlState::Closed) {
    client.close();
  } else if (state != ControlState::Unauthenticated) {
    client.receive(frame(session(ask(client, ClientMessageKind::Login))));
    if (state == ControlState::InMatch) {
      client.receive(frame(joined(ask(client, ClientMessageKind::JoinMatch), 1)));
    }
  }
  events(client);
  sent(client);
  EXPECT_EQ(client.state(), state);
  return client;
}

TEST(ControlClient, NumbersRequestsFromOneAndFramesThem) {
  ControlClient client(0);
  const RequestResult first = client.request(request_of(ClientMessageKind::Register), 0);
  wire::ClientMessage login = request_of(ClientMessageKind::Login);
  login.set_request_id(999);  // replaced
  const RequestResult second = client.request(login, 0);
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first.request_id, 1u);
  EXPECT_EQ(second.request_id, 2u);

  const auto frames = sent(client);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].request_id(), 1u);
  EXPECT_TRUE(frames[0].has_register_account());
  EXPECT_EQ(frames[1].request_id(), 2u);
  EXPECT_EQ(frames[1].login().username(), "ada");
  EXPECT_EQ(client.pending(), 2u);
  EXPECT_EQ(client.counters().frames_out, 2u);
  std::vector<std::uint8_t> none;
  EXPECT_FALSE(client.poll_transmit(none));
}

TEST(ControlClient, RefusesLocallyWhatTheStateTableDoesNotAllowAndSendsNothing) {
  // Spelled out for two states, then every state against the one table.
  ControlClient fresh = client_in(ControlState::Unauthenticated);
  EXPECT_EQ(fresh.request(request_of(ClientMessageKind::JoinMatch), 0).refusal,
            RequestRefusal::WrongState);
  EXPECT_EQ(fresh.request(request_of(ClientMessageKind::Chat), 0).refusal,
            RequestRefusal::WrongState);
  EXPECT_TRUE(sent(fresh).empty());
  EXPECT_EQ(fresh.counters().refused_requests[static_cast<std::size_t>(RequestRefusal::WrongState)],
            2u);
  ControlClient signed_in = client_in(ControlState::Authenticated);
  EXPECT_EQ(signed_in.request(request_of(ClientMessageKind::Login), 0).refusal,
            RequestRefusal::WrongState);
  EXPECT_EQ(signed_in.request(request_of(ClientMessageKind::LeaveMatch), 0).refusal,
            RequestRefusal::WrongState);
  EXPECT_TRUE(signed_in.request(request_of(ClientMessageKind::ListMatches), 0));

  for (const ControlState state : {ControlState::Unauthenticated, ControlState::Authenticated,
                                   ControlState::InMatch, ControlState::Closed}) {
    for (std::size_t k = 0; k < kClientMessageKindCount; ++k) {
      const auto kind = static_cast<ClientMessageKind>(k);
      ControlClient client = client_in(state);
      const RequestResult result = client.request(request_of(kind), 0);
      const auto frames = sent(client);
      if (admits(state, kind)) {
        EXPECT_TRUE(result) << name(kind) << " in " << name(state);
        ASSERT_EQ(frames.size(), 1u);
        EXPECT_EQ(kind_of(frames[0]), kind);
      } else {
        EXPECT_EQ(result.refusal, state == ControlState::Closed ? RequestRefusal::Closed
                                                                : RequestRefusal::WrongState)
            << name(kind) << " in " << name(state);
        EXPECT_EQ(result.request_id, 0u);
        EXPECT_TRUE(frames.empty());
      }
    }
  }
}

TEST(ControlClient, RefusesARequestWithNoBodyOrTooLargeForAFrameWithoutUsingAnId) {
  ControlClient client = client_in(ControlState::InMatch);
  EXPECT_EQ(client.request(wire::ClientMessage{}, 0).refusal, RequestRefusal::NoBody);
  wire::ClientMessage huge;
  huge.mutable_chat()->set_text(std::string(kMaxFramePayloadBytes, 'x'));
  EXPECT_EQ(client.request(huge, 0).refusal, RequestRefusal::TooLarge);
  EXPECT_TRUE(sent(client).empty());
  EXPECT_EQ(ask(client, ClientMessageKind::Ping), 3u);  // login 1, join 2, then this one
}

TEST(ControlClient, RepliesAndMatchResultsMoveTheState) {
  std::vector<std::string> transitions;
  ControlClientConfig config;
  config.on_transition = [&](ControlState from, ControlState to, std::string_view reason) {
    transitions.push_back(std::string(name(from)) + ">" + name(to) + ": " + std::string(reason));
  };
  ControlClient client(0, config);

  // A failed login changes nothing.
  client.receive(frame(error(ask(client, ClientMessageKind::Login), wire::WRONG_CREDENTIALS)));
  EXPECT_EQ(reply_event(client).error()->code(), wire::WRONG_CREDENTIALS);
  EXPECT_EQ(client.state(), ControlState::Unauthenticated);

  client.receive(frame(session(ask(client, ClientMessageKind::Resume))));
  EXPECT_TRUE(reply_event(client).message.has_session());
  EXPECT_EQ(client.state(), ControlState::Authenticated);
  client.receive(frame(joined(ask(client, ClientMessageKind::JoinMatch), 3)));
  EXPECT_EQ(client.state(), ControlState::InMatch);
  client.receive(frame(left(ask(client, ClientMessageKind::LeaveMatch))));
  EXPECT_EQ(client.state(), ControlState::Authenticated);
  client.receive(frame(joined(ask(client, ClientMessageKind::JoinMatch), 4)));
  events(client);

  // The server ends the match on its own: the results arrive and the client is back.
  client.receive(frame(results(4)));
  const auto pushed = events(client);
  ASSERT_EQ(pushed.size(), 1u);
  ASSERT_TRUE(std::holds_alternative<ControlMatchResults>(pushed[0]));
  EXPECT_EQ(std::get<ControlMatchResults>(pushed[0]).results.match_id(), 4u);
  EXPECT_EQ(client.state(), ControlState::Authenticated);

  // NOT_IN_MATCH to a leave means the match already let go: Authenticated as well.
  client.receive(frame(joined(ask(client, ClientMessageKind::JoinMatch), 5)));
  client.receive(frame(error(ask(client, ClientMessageKind::LeaveMatch), wire::NOT_IN_MATCH)));
  EXPECT_EQ(client.state(), ControlState::Authenticated);

  EXPECT_EQ(transitions, (std::vector<std::string>{
                             "unauthenticated>authenticated: signed in as account 7",
                             "authenticated>in_match: joined match 3",
                             "in_match>authenticated: left the match",
                             "authenticated>in_match: joined match 4",
                             "in_match>authenticated: match 4 ended",
                             "authenticated>in_match: joined match 5",
                             "in_match>authenticated: the match had already let go",
                         }));
}

// A resumed connection back in its match (PROTOCOL.md, resume): InMatch at once, so leave and
// chat go out; a login's reply never does this, and a resume without match_id is Authenticated.
TEST(ControlClient, AResumeBackInTheMatchIsInMatch) {
  std::vector<std::string> transitions;
  ControlClientConfig config;
  config.on_transition = [&](ControlState from, ControlState to, std::string_view reason) {
    transitions.push_back(std::string(name(from)) + ">" + name(to) + ": " + std::string(reason));
  };
  ControlClient resumed(0, config);
  wire::ServerMessage back = session(ask(resumed, ClientMessageKind::Resume));
  back.mutable_session()->set_match_id(3);
  resumed.receive(frame(back));
  EXPECT_EQ(reply_event(resumed).message.session().match_id(), 3u);
  EXPECT_EQ(resumed.state(), ControlState::InMatch);
  EXPECT_TRUE(resumed.request(request_of(ClientMessageKind::Chat), 0));
  resumed.receive(frame(left(ask(resumed, ClientMessageKind::LeaveMatch))));
  EXPECT_EQ(resumed.state(), ControlState::Authenticated);
  EXPECT_EQ(transitions, (std::vector<std::string>{
                             "unauthenticated>in_match: resumed account 7 into match 3",
                             "in_match>authenticated: left the match",
                         }));

  ControlClient only_signed_in(0);
  only_signed_in.receive(frame(session(ask(only_signed_in, ClientMessageKind::Resume))));
  EXPECT_EQ(only_signed_in.state(), ControlState::Authenticated);
  EXPECT_EQ(only_signed_in.request(request_of(ClientMessageKind::Chat), 0).refusal,
            RequestRefusal::WrongState);

  ControlClient logged_in(0);
  wire::ServerMessage odd = session(ask(logged_in, ClientMessageKind::Login));
  odd.mutable_session()->set_match_id(3);  // a match_id answering a login means nothing
  logged_in.receive(frame(odd));
  EXPECT_EQ(logged_in.state(), ControlState::Authenticated);
}

TEST(ControlClient, MatchesRepliesToTheirRequestsInAnyOrder) {
  ControlClient client = client_in(ControlState::Authenticated);
  const std::uint32_t list_id = ask(client, ClientMessageKind::ListMatches);
  const std::uint32_t ping_id = ask(client, ClientMessageKind::Ping);
  const std::uint32_t join_id = ask(client, ClientMessageKind::JoinMatch);
  std::vector<std::uint8_t> stream = frame(pong(ping_id));
  const auto more = frame(error(join_id, wire::MATCH_FULL));
  stream.insert(stream.end(), more.begin(), more.end());
  const auto last = frame(list(list_id));
  stream.insert(stream.end(), last.begin(), last.end());
  client.receive(stream);

  const auto all = events(client);
  ASSERT_EQ(all.size(), 3u);
  const auto& first = std::get<ControlReply>(all[0]);
  const auto& second = std::get<ControlReply>(all[1]);
  const auto& third = std::get<ControlReply>(all[2]);
  EXPECT_EQ(first.request_id, ping_id);
  EXPECT_EQ(first.kind, ClientMessageKind::Ping);
  EXPECT_TRUE(first.message.has_pong());
  EXPECT_EQ(second.request_id, join_id);
  EXPECT_EQ(second.kind, ClientMessageKind::JoinMatch);
  ASSERT_NE(second.error(), nullptr);
  EXPECT_EQ(second.error()->code(), wire::MATCH_FULL);
  EXPECT_EQ(third.request_id, list_id);
  EXPECT_EQ(third.kind, ClientMessageKind::ListMatches);
  EXPECT_EQ(third.message.list_matches().matches_size(), 1);
  // An error answer keeps the connection, and the failed join keeps the state.
  EXPECT_EQ(client.state(), ControlState::Authenticated);
  EXPECT_EQ(client.pending(), 0u);
}

/// One refused server input: the client closes with `reason`, counts it, and then ignores bytes
/// and refuses requests.
void expect_refused(ControlClient& client, const std::vector<std::uint8_t>& bytes,
                    ControlCloseReason reason, const std::string& detail_part) {
  client.receive(bytes);
  const ControlClosed closed = closed_event(client);
  EXPECT_EQ(closed.reason, reason) << name(closed.reason) << ": " << closed.detail;
  EXPECT_TRUE(refuses_server(closed.reason));
  EXPECT_NE(closed.detail.find(detail_part), std::string::npos) << closed.detail;
  EXPECT_EQ(client.state(), ControlState::Closed);
  EXPECT_EQ(client.counters().closes[static_cast<std::size_t>(reason)], 1u);
  EXPECT_EQ(client.pending(), 0u);
  const std::uint64_t bytes_in = client.counters().bytes_in;
  client.receive(frame(pong(1)));
  EXPECT_EQ(client.counters().bytes_in, bytes_in);
  EXPECT_TRUE(events(client).empty());
  EXPECT_EQ(client.request(request_of(ClientMessageKind::Ping), 0).refusal, RequestRefusal::Closed);
  std::vector<std::uint8_t> none;
  EXPECT_FALSE(client.poll_transmit(none));
  EXPECT_EQ(client.deadline(), std::nullopt);
}

TEST(ControlClient, AReplyToNoPendingRequestIsRefused) {
  ControlClient client(0);
  ask(client, ClientMessageKind::Login);
  expect_refused(client, frame(pong(9)), ControlCloseReason::UnknownRequest,
                 "answered request 9, which is not pending");
}

TEST(ControlClient, ASecondReplyToTheSameRequestIsRefused) {
  ControlClient client(0);
  const std::uint32_t id = ask(client, ClientMessageKind::Ping);
  client.receive(frame(pong(id)));
  EXPECT_TRUE(reply_event(client).message.has_pong());
  expect_refused(client, frame(pong(id)), ControlCloseReason::UnknownRequest, "not pending");
}

TEST(ControlClient, AReplyThatDoesNotAnswerItsRequestIsRefused) {
  ControlClient client(0);
  const std::uint32_t id = ask(client, ClientMessageKind::Login);
  expect_refused(client, frame(joined(id, 1)), ControlCloseReason::WrongReply,
                 "answered request 1 (login) with a join_match");
}

TEST(ControlClient, AFindMatchIsAnsweredByItsAssignmentAndLeavesTheStateAlone) {
  ControlClient client = client_in(ControlState::Authenticated);
  const std::uint32_t id = ask(client, ClientMessageKind::FindMatch);
  wire::ServerMessage reply;
  reply.set_request_id(id);
  wire::Assignment& assignment = *reply.mutable_find_match()->mutable_assignment();
  assignment.set_connection("127.0.0.1:7777");
  assignment.set_ticket(std::string(32, 't'));
  client.receive(frame(reply));
  const ControlReply answer = reply_event(client);
  EXPECT_EQ(answer.kind, ClientMessageKind::FindMatch);
  EXPECT_EQ(answer.message.find_match().assignment().connection(), "127.0.0.1:7777");
  EXPECT_EQ(client.state(), ControlState::Authenticated);
  // A list answering a find_match does not answer it.
  const std::uint32_t again = ask(client, ClientMessageKind::FindMatch);
  expect_refused(client, frame(list(again)), ControlCloseReason::WrongReply, "find_match");
}

TEST(ControlClient, MatchResultsAnsweringARequestIsRefused) {
  ControlClient client(0);
  const std::uint32_t id = ask(client, ClientMessageKind::Ping);
  wire::ServerMessage message = results(1);
  message.set_request_id(id);
  expect_refused(client, frame(message), ControlCloseReason::WrongReply, "match_results");
}

TEST(ControlClient, AnUnaskedReplyIsRefused) {
  ControlClient client(0);
  expect_refused(client, frame(pong(0)), ControlCloseReason::UnexpectedMessage,
                 "pong with request_id 0");
}

TEST(ControlClient, AnOversizeFrameIsRefusedAtItsHeader) {
  ControlClient client(0);
  ask(client, ClientMessageKind::Ping);
  expect_refused(client, header(kMaxFramePayloadBytes + 1), ControlCloseReason::FrameOversize,
                 "declaring 65537 bytes");
}

TEST(ControlClient, AnEmptyFrameIsRefused) {
  ControlClient client(0);
  expect_refused(client, header(0), ControlCloseReason::FrameEmpty, "declaring 0 bytes");
}

TEST(ControlClient, APayloadThatIsNotAServerMessageIsRefused) {
  ControlClient client(0);
  std::vector<std::uint8_t> garbage = header(5);
  for (std::uint8_t byte : {0xff, 0xff, 0xff, 0xff, 0x0f}) garbage.push_back(byte);
  expect_refused(client, garbage, ControlCloseReason::Malformed, "not a ServerMessage");
}

TEST(ControlClient, AServerMessageWithNoBodyIsRefused) {
  ControlClient client(0);
  expect_refused(client, {0x00, 0x00, 0x00, 0x02, 0x08, 0x01}, ControlCloseReason::MissingBody,
                 "no body (request_id 1)");
}

TEST(ControlClient, TheServersClosingErrorClosesWithItsWords) {
  ControlClient client = client_in(ControlState::Authenticated);
  ask(client, ClientMessageKind::ListMatches);
  client.receive(frame(error(0, wire::SHUTTING_DOWN)));
  const ControlClosed closed = closed_event(client);
  EXPECT_EQ(closed.reason, ControlCloseReason::ServerError);
  EXPECT_FALSE(refuses_server(closed.reason));
  EXPECT_EQ(closed.server_error.code(), wire::SHUTTING_DOWN);
  EXPECT_NE(closed.detail.find("SHUTTING_DOWN: what was expected"), std::string::npos)
      << closed.detail;
  // The stream ending afterwards changes nothing: the server's reason stands.
  client.connection_lost("the server closed the connection");
  EXPECT_TRUE(events(client).empty());
  EXPECT_EQ(client.counters().closes[static_cast<std::size_t>(ControlCloseReason::ServerError)],
            1u);
}

TEST(ControlClient, ConnectionLostAndCloseEndTheClientOnce) {
  ControlClient lost(0);
  ask(lost, ClientMessageKind::Login);
  lost.connection_lost("read failed: connection reset");
  const ControlClosed closed = closed_event(lost);
  EXPECT_EQ(closed.reason, ControlCloseReason::ConnectionLost);
  EXPECT_EQ(closed.detail, "read failed: connection reset");
  std::vector<std::uint8_t> none;
  EXPECT_FALSE(lost.poll_transmit(none));  // the queued login is dropped

  ControlClient closing(0);
  ask(closing, ClientMessageKind::Ping);
  closing.close();
  closing.close();
  EXPECT_EQ(closed_event(closing).reason, ControlCloseReason::Requested);
  EXPECT_TRUE(events(closing).empty());
  EXPECT_EQ(closing.state(), ControlState::Closed);
}

TEST(ControlClient, ARequestWithNoReplyTimesOutAtItsDeadline) {
  ControlClientConfig config;
  config.request_timeout_us = 10 * kSecond;
  config.keep_alive_us = 0;
  ControlClient client(0, config);
  EXPECT_EQ(client.deadline(), std::nullopt);  // nothing pending, no keep-alive

  const std::uint32_t ping_id = ask(client, ClientMessageKind::Ping, 1 * kSecond);
  ask(client, ClientMessageKind::Login, 4 * kSecond);
  EXPECT_EQ(client.deadline(), 11 * kSecond);
  client.update(11 * kSecond - 1);
  EXPECT_TRUE(events(client).empty());
  // The ping's answer comes in time; the login's deadline is next.
  client.receive(frame(pong(ping_id)));
  events(client);
  EXPECT_EQ(client.deadline(), 14 * kSecond);
  client.update(14 * kSecond);
  const ControlClosed closed = closed_event(client);
  EXPECT_EQ(closed.reason, ControlCloseReason::RequestTimeout);
  EXPECT_EQ(closed.detail, "request 2 (login) had no reply within 10000 ms");
  EXPECT_FALSE(refuses_server(closed.reason));
  EXPECT_EQ(client.state(), ControlState::Closed);
}

TEST(ControlClient, AQuietClientPingsToStayOpenAndConsumesThePong) {
  ControlClientConfig config;
  config.request_timeout_us = 10 * kSecond;
  config.keep_alive_us = 30 * kSecond;
  ControlClient client(0, config);
  EXPECT_EQ(client.deadline(), 30 * kSecond);
  client.update(30 * kSecond - 1);
  EXPECT_TRUE(sent(client).empty());
  client.update(30 * kSecond);
  auto frames = sent(client);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_TRUE(frames[0].has_ping());
  EXPECT_EQ(client.counters().keep_alives, 1u);
  EXPECT_EQ(client.deadline(), 40 * kSecond);  // the ping's own reply deadline

  client.receive(frame(pong(frames[0].request_id())));
  EXPECT_TRUE(events(client).empty());  // this client's own ping: no event
  EXPECT_EQ(client.pending(), 0u);
  // A request counts as traffic: the next ping is due 30 s after it.
  const std::uint32_t id = ask(client, ClientMessageKind::Login, 45 * kSecond);
  EXPECT_EQ(sent(client).size(), 1u);
  client.receive(frame(session(id)));
  events(client);
  EXPECT_EQ(client.deadline(), 75 * kSecond);
  client.update(74 * kSecond);
  EXPECT_TRUE(sent(client).empty());
  client.update(75 * kSecond);
  frames = sent(client);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_TRUE(frames[0].has_ping());
}

TEST(ControlClient, AKeepAlivePingWithNoReplyTimesOut) {
  ControlClientConfig config;
  config.request_timeout_us = 10 * kSecond;
  config.keep_alive_us = 30 * kSecond;
  ControlClient client(0, config);
  client.update(30 * kSecond);
  client.update(40 * kSecond);
  EXPECT_EQ(closed_event(client).detail, "request 1 (ping) had no reply within 10000 ms");
}

/// The server's side of one conversation: the client's pipelined requests and every answer.
struct Conversation {
  std::vector<std::uint8_t> stream;
  ControlClient client{0};

  Conversation() {
    const std::uint32_t login = ask(client, ClientMessageKind::Login);
    const std::uint32_t ping = ask(client, ClientMessageKind::Ping);
    append(session(login));
    append(pong(ping));
    append(results(2));
    append(error(0, wire::SHUTTING_DOWN));
  }
  void append(const wire::ServerMessage& message) {
    const auto bytes = frame(message);
    stream.insert(stream.end(), bytes.begin(), bytes.end());
  }
};

std::string describe(const std::vector<ControlEvent>& all) {
  std::string text;
  for (const ControlEvent& event : all) {
    if (const auto* reply = std::get_if<ControlReply>(&event)) {
      text += "reply " + std::to_string(reply->request_id) + " " + name(reply->kind) + " " +
              reply->message.ShortDebugString() + "\n";
    } else if (const auto* pushed = std::get_if<ControlMatchResults>(&event)) {
      text += "results " + pushed->results.ShortDebugString() + "\n";
    } else {
      const auto& closed = std::get<ControlClosed>(event);
      text += std::string("closed ") + name(closed.reason) + " " + closed.detail + "\n";
    }
  }
  return text;
}

TEST(ControlClient, BytesSplitAtEveryBoundaryGiveTheSameEvents) {
  Conversation whole;
  whole.client.receive(whole.stream);
  const std::string expected = describe(events(whole.client));
  EXPECT_EQ(expected.substr(0, 8), "reply 1 ");
  EXPECT_NE(expected.find("closed server_error"), std::string::npos) << expected;

  for (std::size_t split = 0; split <= whole.stream.size(); ++split) {
    Conversation two;
    const std::span<const std::uint8_t> stream(two.stream);
    two.client.receive(stream.first(split));
    two.client.receive(stream.subspan(split));
    EXPECT_EQ(describe(events(two.client)), expected) << "split at byte " << split;
  }
  Conversation bytewise;
  for (std::uint8_t byte : bytewise.stream) {
    bytewise.client.receive(std::span<const std::uint8_t>(&byte, 1));
  }
  EXPECT_EQ(describe(events(bytewise.client)), expected);
  EXPECT_EQ(bytewise.client.counters().frames_in, 4u);
  EXPECT_EQ(bytewise.client.counters().bytes_in, bytewise.stream.size());
}

}  // namespace
}  // namespace ricochet::proto::control_client_test
