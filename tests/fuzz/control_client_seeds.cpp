// Writes the seed corpus of control_client_fuzz: what a server sends to the fuzz target's
// pipeline (register 1, login 2, resume 3, ping 4), whole, byte by byte and in small chunks, and
// each kind of server input the client refuses (an unknown or wrong reply, an unasked one, an
// oversize, empty, garbage or bodiless frame). Run by `tools/fuzz.sh --seeds`; the output is
// committed in tests/fuzz/corpus/control_client/.
//
//   control_client_seeds DIR

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "ricochet/proto/frame.h"

namespace {

using ricochet::wire::ServerMessage;

ServerMessage with_id(std::uint32_t request_id) {
  ServerMessage m;
  m.set_request_id(request_id);
  return m;
}

/// The answers to the pipeline, then what a match and a stopping server send unasked.
std::vector<ServerMessage> conversation() {
  std::vector<ServerMessage> messages;
  messages.push_back(with_id(1));
  messages.back().mutable_register_account()->set_account_id(7);
  messages.push_back(with_id(2));
  messages.back().mutable_session()->set_account_id(7);
  messages.back().mutable_session()->set_username("ada");
  messages.back().mutable_session()->set_session_token(std::string(64, 'f'));
  messages.back().mutable_session()->set_expires_unix_ms(1'700'000'000'000);
  messages.push_back(with_id(3));
  messages.back().mutable_error()->set_code(ricochet::wire::WRONG_STATE);
  messages.back().mutable_error()->set_message("resume is not allowed while authenticated");
  messages.push_back(with_id(4));
  messages.back().mutable_pong()->set_client_time_us(1);
  messages.back().mutable_pong()->set_server_unix_ms(1'700'000'000'000);
  messages.push_back(with_id(0));
  auto* results = messages.back().mutable_match_results();
  results->set_match_id(1);
  results->set_mode("ffa");
  results->set_map("arena");
  auto* player = results->add_players();
  player->set_account_id(7);
  player->set_username("ada");
  player->set_kills(3);
  player->set_rating_before(1500);
  player->set_rating_after(1516);
  messages.push_back(with_id(0));
  messages.back().mutable_error()->set_code(ricochet::wire::SHUTTING_DOWN);
  messages.back().mutable_error()->set_message("the server is stopping");
  return messages;
}

std::vector<std::uint8_t> frames(const std::vector<ServerMessage>& messages, bool& ok) {
  std::vector<std::uint8_t> bytes;
  for (const ServerMessage& message : messages) ok &= ricochet::proto::append_frame(message, bytes);
  return bytes;
}

bool write(const std::string& dir, const std::string& name, std::uint8_t chunk_pattern,
           const std::vector<std::uint8_t>& stream) {
  const std::string path = dir + "/" + name + ".bin";
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  std::fputc(chunk_pattern, file);
  const bool ok = std::fwrite(stream.data(), 1, stream.size(), file) == stream.size();
  return std::fclose(file) == 0 && ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: control_client_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = true;
  const std::vector<std::uint8_t> all = frames(conversation(), ok);
  ok &= write(dir, "conversation_whole", 255, all);
  ok &= write(dir, "conversation_bytewise", 0, all);
  ok &= write(dir, "conversation_chunks7", 6, all);

  ServerMessage unknown = with_id(9);
  unknown.mutable_pong();
  ok &= write(dir, "unknown_request", 255, frames({unknown}, ok));
  ServerMessage wrong = with_id(2);
  wrong.mutable_join_match()->set_match_id(1);
  ok &= write(dir, "wrong_reply", 255, frames({wrong}, ok));
  ServerMessage unasked = with_id(0);
  unasked.mutable_chat();
  ok &= write(dir, "unasked_reply", 255, frames({unasked}, ok));
  ok &= write(dir, "oversize", 255, {0x00, 0x01, 0x00, 0x01});
  ok &= write(dir, "empty", 255, {0x00, 0x00, 0x00, 0x00});
  ok &= write(dir, "garbage", 255, {0x00, 0x00, 0x00, 0x05, 0xff, 0xff, 0xff, 0xff, 0x0f});
  ok &= write(dir, "no_body", 255, {0x00, 0x00, 0x00, 0x02, 0x08, 0x01});
  ok &= write(dir, "partial", 3, {0x00, 0x00, 0x00, 0x20, 0x08, 0x01});
  if (!ok) {
    std::fprintf(stderr, "control_client_seeds: cannot write the seeds into %s\n", dir.c_str());
    return 1;
  }
  return 0;
}
