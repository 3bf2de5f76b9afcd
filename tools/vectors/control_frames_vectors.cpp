/// tests/vectors/control_frames.txt: one frame of every ClientMessage and ServerMessage body, as
/// the C++ end writes them (proto::append_frame), and the stream headers a reader refuses.
///   frame direction=client|server body=NAME request_id=N bytes=HEX
///     NAME is the body's oneof field name in control.proto; HEX is the whole frame (length
///     prefix and payload). A reader yields one payload from HEX; it parses as the direction's
///     message with that body and request id, and serialises back to the same bytes.
///   refused header=HEX reason=frame_oversize|frame_empty length=N
///     A stream that begins with these 4 bytes is refused from the header alone.
///   assignment bytes=HEX connection=HOST:PORT host=H control_port=N game_port=N
///              certificate_sha256=HEX64 match_id=N mode=M [map=M] ticket=HEX
///              ticket_expires_in_ms=N on_this_server=0|1
///     A find_match reply frame (PROTOCOL.md, Placement) and the fields of its Assignment, the
///     connection split into host and port (an IPv6 host without its brackets; map left out when
///     empty). The same frame is also a `frame` record.
///   placement_error bytes=HEX code=NAME value=N
///     An Error frame with one of the placement codes (60-64), its name and number.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ricochet/proto/frame.h"
#include "vector_file.h"

namespace ricochet::vectors {
namespace {

/// A ticket's 32 bytes (Assignment.ticket, JoinMatchRequest.ticket).
std::string ticket_bytes() {
  std::string ticket(32, '\0');
  for (std::size_t i = 0; i < ticket.size(); ++i) ticket[i] = static_cast<char>(0xa0 + i);
  return ticket;
}
constexpr const char* kFingerprint =
    "4ca9e7a1b0c2d3e4f5061728394a5b6c7d8e9fa0b1c2d3e4f50617283940ab25";

template <class Message>
void add_frame(VectorFile& file, const char* direction, const char* body, const Message& message) {
  std::vector<std::uint8_t> frame;
  if (!proto::append_frame(message, frame)) throw std::logic_error("unframeable vector");
  file.add(Record("frame")
               .word("direction", direction)
               .word("body", body)
               .number("request_id", message.request_id())
               .bytes("bytes", frame));
}

void add_client_frames(VectorFile& file) {
  wire::ClientMessage m;
  m.set_request_id(1);
  m.mutable_register_account()->set_username("alice_01");
  m.mutable_register_account()->set_password("correct horse battery");
  add_frame(file, "client", "register_account", m);
  m.Clear();
  m.set_request_id(2);
  m.mutable_login()->set_username("alice_01");
  m.mutable_login()->set_password("p\xc3\xa4ssw\xc3\xb6rd \xe2\x9c\x93");  // UTF-8
  add_frame(file, "client", "login", m);
  m.Clear();
  m.set_request_id(3);
  m.mutable_resume()->set_session_token(std::string(64, 'a'));
  add_frame(file, "client", "resume", m);
  m.Clear();
  m.set_request_id(4);
  m.mutable_list_matches();
  add_frame(file, "client", "list_matches", m);
  m.Clear();
  m.set_request_id(5);
  m.mutable_create_match()->set_name("Friday night");
  m.mutable_create_match()->set_max_players(8);
  m.mutable_create_match()->set_map("foundry");
  add_frame(file, "client", "create_match", m);
  m.Clear();
  m.set_request_id(6);
  m.mutable_join_match()->set_match_id(3);
  add_frame(file, "client", "join_match", m);
  m.Clear();
  m.set_request_id(7);
  m.mutable_leave_match();
  add_frame(file, "client", "leave_match", m);
  m.Clear();
  m.set_request_id(8);
  m.mutable_chat()->set_text("gg \xf0\x9f\x8e\xaf");
  add_frame(file, "client", "chat", m);
  m.Clear();
  m.set_request_id(4294967295u);  // the last request id before the wrap to 1
  m.mutable_ping()->set_client_time_us(1733450000123456ull);
  add_frame(file, "client", "ping", m);
  m.Clear();
  m.set_request_id(9);
  m.mutable_logout();
  add_frame(file, "client", "logout", m);
  m.Clear();
  m.set_request_id(10);
  m.mutable_find_match()->set_mode("tdm");
  m.mutable_find_match()->set_map("foundry");
  add_frame(file, "client", "find_match", m);
  m.Clear();
  m.set_request_id(11);
  m.mutable_join_match()->set_ticket(ticket_bytes());
  add_frame(file, "client", "join_match", m);
}

/// A placed seat: where the ticket is presented and what it holds.
struct Placed {
  const char* host;  ///< as Assignment.connection writes it (IPv6 in brackets)
  const char* bare_host;
  std::uint32_t control_port;
  std::uint32_t game_port;
  std::uint32_t match_id;  ///< 0: a new match is made there
  const char* mode;
  const char* map;  ///< empty: that server's choice
  bool on_this_server;
};

void add_assignment(VectorFile& file, std::uint32_t request_id, const Placed& placed) {
  wire::ServerMessage m;
  m.set_request_id(request_id);
  wire::Assignment& a = *m.mutable_find_match()->mutable_assignment();
  const std::string connection =
      std::string(placed.host) + ":" + std::to_string(placed.control_port);
  a.set_connection(connection);
  a.set_game_port(placed.game_port);
  a.set_certificate_sha256(kFingerprint);
  a.set_match_id(placed.match_id);
  a.set_mode(placed.mode);
  a.set_map(placed.map);
  a.set_ticket(ticket_bytes());
  a.set_ticket_expires_in_ms(29'875);
  a.set_on_this_server(placed.on_this_server);
  add_frame(file, "server", "find_match", m);
  std::vector<std::uint8_t> frame;
  proto::append_frame(m, frame);
  Record record("assignment");
  record.bytes("bytes", frame)
      .bytes("connection", connection)
      .word("host", placed.bare_host)
      .number("control_port", placed.control_port)
      .number("game_port", placed.game_port)
      .word("certificate_sha256", kFingerprint)
      .number("match_id", placed.match_id)
      .word("mode", placed.mode);
  if (*placed.map != '\0') record.word("map", placed.map);
  file.add(record.bytes("ticket", ticket_bytes())
               .number("ticket_expires_in_ms", a.ticket_expires_in_ms())
               .number("on_this_server", placed.on_this_server ? 1 : 0));
}

/// find_match replies (one elsewhere, one on this server, one on an IPv6 host) and every
/// placement error.
void add_placement_frames(VectorFile& file) {
  add_assignment(file, 10, {"10.0.0.2", "10.0.0.2", 7787, 7788, 3, "tdm", "foundry", false});
  add_assignment(file, 10, {"127.0.0.1", "127.0.0.1", 7777, 7778, 0, "ffa", "", true});
  add_assignment(file, 10,
                 {"[fd00::2]", "fd00::2", 7777, 7778, 4294967295u, "ffa", "arena", false});
  for (const wire::ErrorCode code :
       {wire::NO_SERVER_AVAILABLE, wire::UNKNOWN_MODE_OR_MAP, wire::FIND_MATCH_RATE_LIMITED,
        wire::UNKNOWN_TICKET, wire::EXPIRED_TICKET}) {
    wire::ServerMessage m;
    m.set_request_id(code < wire::UNKNOWN_TICKET ? 10 : 11);
    m.mutable_error()->set_code(code);
    m.mutable_error()->set_message("placement refused: " + wire::ErrorCode_Name(code));
    add_frame(file, "server", "error", m);
    std::vector<std::uint8_t> frame;
    proto::append_frame(m, frame);
    file.add(Record("placement_error")
                 .bytes("bytes", frame)
                 .word("code", wire::ErrorCode_Name(code))
                 .number("value", code));
  }
}

void add_server_frames(VectorFile& file) {
  wire::ServerMessage m;
  m.set_request_id(1);
  m.mutable_error()->set_code(wire::DUPLICATE_USERNAME);
  m.mutable_error()->set_message("the username alice_01 is taken");
  add_frame(file, "server", "error", m);
  m.Clear();
  m.set_request_id(1);
  m.mutable_register_account()->set_account_id(42);
  add_frame(file, "server", "register_account", m);
  m.Clear();
  m.set_request_id(2);
  wire::SessionReply& session = *m.mutable_session();
  session.set_account_id(42);
  session.set_username("alice_01");
  session.set_session_token(std::string(64, 'f'));
  session.set_expires_unix_ms(1733536400000);
  add_frame(file, "server", "session", m);
  m.Clear();
  m.set_request_id(4);
  for (std::uint32_t id = 1; id <= 2; ++id) {
    wire::MatchInfo& match = *m.mutable_list_matches()->add_matches();
    match.set_match_id(id);
    match.set_name(id == 1 ? "arena-1" : "Friday night");
    match.set_mode(id == 1 ? "ffa" : "tdm");
    match.set_map("foundry");
    match.set_players(id * 3);
    match.set_max_players(16);
  }
  add_frame(file, "server", "list_matches", m);
  m.Clear();
  m.set_request_id(6);
  wire::JoinMatchReply& join = *m.mutable_join_match();
  join.set_match_id(3);
  join.set_udp_port(7778);
  join.set_connect_token(std::string(1024, '\x5a'));
  join.set_client_to_server_key(std::string(32, '\x01'));
  join.set_server_to_client_key(std::string(32, '\x02'));
  join.set_token_expires_in_ms(10000);
  join.set_timeout_s(5);
  join.set_tick_rate_hz(60);
  join.set_snapshot_rate_hz(30);
  add_frame(file, "server", "join_match", m);
  m.Clear();
  m.set_request_id(7);
  m.mutable_leave_match();
  add_frame(file, "server", "leave_match", m);
  m.Clear();
  m.set_request_id(8);
  m.mutable_chat();
  add_frame(file, "server", "chat", m);
  m.Clear();
  m.set_request_id(4294967295u);
  m.mutable_pong()->set_client_time_us(1733450000123456ull);
  m.mutable_pong()->set_server_unix_ms(1733450000200);
  add_frame(file, "server", "pong", m);
  m.Clear();
  m.set_request_id(0);  // server-initiated
  wire::MatchResults& results = *m.mutable_match_results();
  results.set_match_id(3);
  results.set_map("foundry");
  results.set_mode("ffa");
  wire::PlayerMatchResult& player = *results.add_players();
  player.set_account_id(42);
  player.set_username("alice_01");
  player.set_kills(7);
  player.set_deaths(2);
  player.set_score(7);
  player.set_won(true);
  player.set_rating_before(1500.0);
  player.set_rating_after(1516.25);
  add_frame(file, "server", "match_results", m);
  m.Clear();
  m.set_request_id(9);
  m.mutable_logout();
  add_frame(file, "server", "logout", m);
}

}  // namespace

std::string write_control_frames_vectors() {
  VectorFile file("control_frames",
                  "One frame of every control-channel body, as proto::append_frame writes it,\n"
                  "and the stream headers a frame reader refuses (tools/vectors/"
                  "control_frames_vectors.cpp).");
  add_client_frames(file);
  add_server_frames(file);
  add_placement_frames(file);
  const std::uint8_t oversize[] = {0x00, 0x01, 0x00, 0x01};
  file.add(Record("refused")
               .bytes("header", oversize)
               .word("reason", "frame_oversize")
               .number("length", 65537));
  const std::uint8_t huge[] = {0xff, 0xff, 0xff, 0xff};
  file.add(Record("refused")
               .bytes("header", huge)
               .word("reason", "frame_oversize")
               .number("length", 4294967295));
  const std::uint8_t empty[] = {0x00, 0x00, 0x00, 0x00};
  file.add(
      Record("refused").bytes("header", empty).word("reason", "frame_empty").number("length", 0));
  return file.text();
}

}  // namespace ricochet::vectors
