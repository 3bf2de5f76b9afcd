/// tests/vectors/control_session.txt: scenarios of the control channel's client state machine
/// (proto::ControlClient, default configuration: 60 s request timeout, 30 s keep-alive), each
/// from a fresh client made at time 0, as steps with what the C++ client did after each.
///   scenario name=NAME                       a fresh client at 0 ms
///   request at_ms=T message=HEX id=N         request(ClientMessage HEX, T): queued as id N, or
///   request at_ms=T message=HEX refusal=R    refused locally for R (wrong_state, no_body ...)
///   receive bytes=HEX                        receive(HEX): the server's bytes
///   update at_ms=T                           update(T)
///   transmit bytes=HEX                       after the step, poll_transmit gave HEX (whole frames)
///   reply id=N kind=K body=B [code=C]        after the step, an event: the reply to request N of
///                                            kind K with body B (an Error's code C)
///   match_results match_id=N                 after the step, an event: MatchResults
///   closed reason=R [code=C]                 after the step, an event: closed for R (the server's
///                                            code C for server_error)
///   state value=S pending=N                  after the step (and its events): the state and the
///                                            requests still pending
/// A second implementation replays the steps and must see the same records in the same order.

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/proto/control_client.h"
#include "ricochet/proto/frame.h"
#include "vector_file.h"

namespace ricochet::vectors {
namespace {

constexpr proto::TimeUs kMicrosPerMs = 1000;

std::string body_name(const wire::ServerMessage& message) {
  const auto* field = wire::ServerMessage::descriptor()->FindFieldByNumber(message.body_case());
  return field ? field->name() : "none";
}

std::vector<std::uint8_t> frame_of(const wire::ServerMessage& message) {
  std::vector<std::uint8_t> frame;
  proto::append_frame(message, frame);
  return frame;
}

/// One scenario: drives a ControlClient and records every step and what followed it.
class Scenario {
 public:
  Scenario(VectorFile& file, const char* name) : file_(file), client_(0) {
    file_.add(Record("scenario").word("name", name));
  }

  void request(const wire::ClientMessage& message, std::int64_t at_ms) {
    Record record("request");
    record.number("at_ms", at_ms).bytes("message", message.SerializeAsString());
    const proto::RequestResult result = client_.request(message, at_ms * kMicrosPerMs);
    if (result) {
      record.number("id", result.request_id);
    } else {
      record.word("refusal", proto::name(*result.refusal));
    }
    file_.add(record);
    after();
  }
  void receive(const std::vector<std::uint8_t>& bytes) {
    file_.add(Record("receive").bytes("bytes", bytes));
    client_.receive(bytes);
    after();
  }
  void reply(const wire::ServerMessage& message) { receive(frame_of(message)); }
  void update(std::int64_t at_ms) {
    file_.add(Record("update").number("at_ms", at_ms));
    client_.update(at_ms * kMicrosPerMs);
    after();
  }

 private:
  void after() {
    std::vector<std::uint8_t> bytes;
    if (client_.poll_transmit(bytes)) file_.add(Record("transmit").bytes("bytes", bytes));
    proto::ControlEvent event;
    while (client_.poll_event(event)) {
      if (const auto* reply = std::get_if<proto::ControlReply>(&event)) {
        Record record("reply");
        record.number("id", reply->request_id)
            .word("kind", proto::name(reply->kind))
            .word("body", body_name(reply->message));
        if (const wire::Error* error = reply->error()) {
          record.word("code", wire::ErrorCode_Name(error->code()));
        }
        file_.add(record);
      } else if (const auto* results = std::get_if<proto::ControlMatchResults>(&event)) {
        file_.add(Record("match_results").number("match_id", results->results.match_id()));
      } else if (const auto* closed = std::get_if<proto::ControlClosed>(&event)) {
        Record record("closed");
        record.word("reason", proto::name(closed->reason));
        if (closed->reason == proto::ControlCloseReason::ServerError) {
          record.word("code", wire::ErrorCode_Name(closed->server_error.code()));
        }
        file_.add(record);
      }
    }
    file_.add(Record("state")
                  .word("value", proto::name(client_.state()))
                  .number("pending", static_cast<std::int64_t>(client_.pending())));
  }

  VectorFile& file_;
  proto::ControlClient client_;
};

wire::ClientMessage login() {
  wire::ClientMessage m;
  m.mutable_login()->set_username("alice_01");
  m.mutable_login()->set_password("correct horse battery");
  return m;
}
wire::ClientMessage list() {
  wire::ClientMessage m;
  m.mutable_list_matches();
  return m;
}
wire::ClientMessage create() {
  wire::ClientMessage m;
  m.mutable_create_match()->set_name("Friday night");
  m.mutable_create_match()->set_max_players(8);
  return m;
}
wire::ClientMessage join(std::uint32_t match) {
  wire::ClientMessage m;
  m.mutable_join_match()->set_match_id(match);
  return m;
}
wire::ClientMessage leave() {
  wire::ClientMessage m;
  m.mutable_leave_match();
  return m;
}
wire::ClientMessage chat(const std::string& text) {
  wire::ClientMessage m;
  m.mutable_chat()->set_text(text);
  return m;
}
wire::ClientMessage logout() {
  wire::ClientMessage m;
  m.mutable_logout();
  return m;
}

wire::ServerMessage session_reply(std::uint32_t id) {
  wire::ServerMessage m;
  m.set_request_id(id);
  m.mutable_session()->set_account_id(42);
  m.mutable_session()->set_username("alice_01");
  m.mutable_session()->set_session_token(std::string(64, 'a'));
  return m;
}
wire::ServerMessage error_reply(std::uint32_t id, wire::ErrorCode code) {
  wire::ServerMessage m;
  m.set_request_id(id);
  m.mutable_error()->set_code(code);
  m.mutable_error()->set_message("because");
  return m;
}
wire::ServerMessage join_reply(std::uint32_t id, std::uint32_t match) {
  wire::ServerMessage m;
  m.set_request_id(id);
  m.mutable_join_match()->set_match_id(match);
  m.mutable_join_match()->set_udp_port(7778);
  return m;
}

void sign_in_and_play(VectorFile& file) {
  Scenario s(file, "sign_in_and_play");
  s.request(list(), 0);  // refused: not signed in yet
  s.request(login(), 5);
  s.request(list(), 6);  // still refused: the state is the replies'
  s.reply(session_reply(1));
  s.request(list(), 10);
  s.request(create(), 11);
  wire::ServerMessage created;
  created.set_request_id(3);
  created.mutable_create_match()->mutable_match()->set_match_id(9);
  s.reply(created);  // out of order
  wire::ServerMessage listed;
  listed.set_request_id(2);
  listed.mutable_list_matches()->add_matches()->set_match_id(9);
  s.reply(listed);
  s.request(chat("too early"), 20);  // refused: not in a match
  s.request(join(9), 21);
  s.reply(join_reply(4, 9));
  s.request(chat("gg"), 30);
  wire::ServerMessage chatted;
  chatted.set_request_id(5);
  chatted.mutable_chat();
  s.reply(chatted);
  wire::ServerMessage results;
  results.mutable_match_results()->set_match_id(9);
  s.reply(results);        // ends the match
  s.request(leave(), 40);  // refused: no longer in a match
  s.request(join(9), 41);
  s.reply(join_reply(6, 9));
  s.request(leave(), 50);
  s.reply(error_reply(7, wire::NOT_IN_MATCH));  // the match had already let go
  s.request(logout(), 60);
  wire::ServerMessage out;
  out.set_request_id(8);
  out.mutable_logout();
  s.reply(out);
  s.request(list(), 70);
}

void refused_requests(VectorFile& file) {
  Scenario s(file, "refused_requests");
  s.request(wire::ClientMessage(), 0);  // no body
  s.request(join(1), 0);
  s.request(leave(), 0);
  s.request(chat("hi"), 0);
  s.request(logout(), 0);
  s.request(create(), 0);
  s.request(login(), 1);
  s.reply(error_reply(1, wire::WRONG_CREDENTIALS));  // a failed login changes nothing
  s.request(login(), 2);
  s.reply(session_reply(2));
  s.request(join(3), 3);
  s.reply(join_reply(3, 3));
  s.request(login(), 5);  // signed in already
}

wire::ClientMessage resume() {
  wire::ClientMessage m;
  m.mutable_resume()->set_session_token(std::string(64, 'a'));
  return m;
}

/// A resume whose reply names the match the sign-in plays (PROTOCOL.md, resume, "Back in the
/// match"): InMatch at once; then one without it, only signed in.
void resume_back_in_match(VectorFile& file) {
  {
    Scenario s(file, "resume_back_in_match");
    s.request(resume(), 0);
    wire::ServerMessage back = session_reply(1);
    back.mutable_session()->clear_session_token();  // a resume's reply: the client keeps its own
    back.mutable_session()->set_match_id(9);
    s.reply(back);
    s.request(chat("back"), 10);
    wire::ServerMessage chatted;
    chatted.set_request_id(2);
    chatted.mutable_chat();
    s.reply(chatted);
    s.request(leave(), 20);
    wire::ServerMessage left;
    left.set_request_id(3);
    left.mutable_leave_match();
    s.reply(left);
    s.request(chat("gone"), 30);  // refused: left
  }
  Scenario s(file, "resume_signed_in_only");
  s.request(resume(), 0);
  wire::ServerMessage signed_in = session_reply(1);
  signed_in.mutable_session()->clear_session_token();
  s.reply(signed_in);
  s.request(leave(), 10);  // refused: not in a match
}

/// PROTOCOL.md, Placement: find_match leaves the state as it was (an assignment seats nobody
/// yet) and its errors too; on the assigned server, a resume, the ticket's errors, then the join
/// with it puts the connection in the match, where find_match is still allowed.
void placement(VectorFile& file) {
  wire::ClientMessage find;
  find.mutable_find_match()->set_mode("tdm");
  const std::string ticket(32, '\xa5');
  {
    Scenario s(file, "placement_find_match");
    s.request(find, 0);  // refused: not signed in
    s.request(login(), 1);
    s.reply(session_reply(1));
    s.request(find, 2);
    wire::ServerMessage found;
    found.set_request_id(2);
    wire::Assignment& assignment = *found.mutable_find_match()->mutable_assignment();
    assignment.set_connection("10.0.0.2:7787");
    assignment.set_game_port(7788);
    assignment.set_certificate_sha256(std::string(64, 'c'));
    assignment.set_match_id(3);
    assignment.set_mode("tdm");
    assignment.set_ticket(ticket);
    assignment.set_ticket_expires_in_ms(30'000);
    s.reply(found);
    std::uint32_t id = 3;
    for (const wire::ErrorCode code :
         {wire::NO_SERVER_AVAILABLE, wire::UNKNOWN_MODE_OR_MAP, wire::FIND_MATCH_RATE_LIMITED}) {
      s.request(find, 3 + id);
      s.reply(error_reply(id++, code));
    }
    s.request(find, 60'006);
    s.update(120'005);
    s.update(120'006);  // unanswered for 60 s: it times out like any request
  }
  Scenario s(file, "placement_join_with_ticket");
  s.request(resume(), 0);
  wire::ServerMessage resumed = session_reply(1);
  resumed.mutable_session()->clear_session_token();
  s.reply(resumed);
  wire::ClientMessage join;
  join.mutable_join_match()->set_ticket(ticket);
  s.request(join, 1);
  s.reply(error_reply(2, wire::UNKNOWN_TICKET));
  s.request(join, 2);
  s.reply(error_reply(3, wire::EXPIRED_TICKET));
  s.request(join, 3);
  s.reply(join_reply(4, 3));
  s.request(find, 4);  // allowed in the match
}

void keep_alive_and_timeout(VectorFile& file) {
  Scenario s(file, "keep_alive_and_timeout");
  s.update(29'999);
  s.update(30'000);  // a keep-alive ping, id 1
  wire::ServerMessage pong;
  pong.set_request_id(1);
  pong.mutable_pong()->set_client_time_us(30'000'000);
  s.reply(pong);  // consumed: no event
  s.request(login(), 40'000);
  s.update(69'999);
  s.update(70'000);   // 30 s since the login was sent: a ping while the login waits
  s.update(100'000);  // the login had no reply within 60 s
  s.request(login(), 100'001);
}

void split_frames(VectorFile& file) {
  Scenario s(file, "split_frames");
  s.request(login(), 0);
  std::vector<std::uint8_t> frame = frame_of(session_reply(1));
  wire::ServerMessage results;
  results.mutable_match_results()->set_match_id(4);
  const std::vector<std::uint8_t> second = frame_of(results);
  frame.insert(frame.end(), second.begin(), second.end());
  s.receive({frame.begin(), frame.begin() + 3});  // not even the header
  s.receive({frame.begin() + 3, frame.begin() + 20});
  s.receive({frame.begin() + 20, frame.end()});  // the rest of one frame and all of the next
}

/// One scenario per way the server's bytes are refused: a client signed in, a list_matches
/// pending (id 2), then `bytes`.
void refused_server(VectorFile& file, const char* name, const std::vector<std::uint8_t>& bytes) {
  Scenario s(file, name);
  s.request(login(), 0);
  s.reply(session_reply(1));
  s.request(list(), 1);
  s.receive(bytes);
  s.request(list(), 2);  // refused: closed
}

void refused_servers(VectorFile& file) {
  refused_server(file, "refuse_oversize", {0x00, 0x01, 0x00, 0x01, 0x08});
  refused_server(file, "refuse_empty", {0x00, 0x00, 0x00, 0x00});
  refused_server(file, "refuse_malformed", {0x00, 0x00, 0x00, 0x02, 0xff, 0xff});
  refused_server(file, "refuse_missing_body", {0x00, 0x00, 0x00, 0x02, 0x08, 0x02});
  wire::ServerMessage unknown;
  unknown.set_request_id(77);
  unknown.mutable_list_matches();
  refused_server(file, "refuse_unknown_request", frame_of(unknown));
  wire::ServerMessage wrong;
  wrong.set_request_id(2);
  wrong.mutable_logout();
  refused_server(file, "refuse_wrong_reply", frame_of(wrong));
  wire::ServerMessage unasked;
  unasked.mutable_pong();
  refused_server(file, "refuse_unexpected_message", frame_of(unasked));
  refused_server(file, "server_closes", frame_of(error_reply(0, wire::SHUTTING_DOWN)));
  // A reply to the pending request, then a frame the client refuses, in one read.
  wire::ServerMessage listed;
  listed.set_request_id(2);
  listed.mutable_list_matches();
  std::vector<std::uint8_t> both = frame_of(listed);
  both.insert(both.end(), {0x00, 0x00, 0x00, 0x00});
  refused_server(file, "reply_then_refuse", both);
}

}  // namespace

std::string write_control_session_vectors() {
  VectorFile file("control_session",
                  "Scenarios of proto::ControlClient (tools/vectors/control_session_vectors.cpp):\n"
                  "requests, the server's bytes and the time in; frames, events and states out.");
  sign_in_and_play(file);
  refused_requests(file);
  resume_back_in_match(file);
  placement(file);
  keep_alive_and_timeout(file);
  split_frames(file);
  refused_servers(file);
  return file.text();
}

}  // namespace ricochet::vectors
