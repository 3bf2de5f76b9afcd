// Writes the seed corpus of control_frame_fuzz: streams of valid control frames (every client
// message kind, pipelined, split in small chunks) and the refused kinds (oversize, empty,
// garbage, no body). Run by `tools/fuzz.sh --seeds`; the output is committed in
// tests/fuzz/corpus/control_frame/.
//
//   control_frame_seeds DIR

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "ricochet/proto/frame.h"

namespace {

using ricochet::wire::ClientMessage;

std::vector<ClientMessage> one_of_each() {
  std::vector<ClientMessage> messages(9);
  messages[0].mutable_register_account()->set_username("ada");
  messages[0].mutable_register_account()->set_password("lovelace1");
  messages[1].mutable_login()->set_username("ada");
  messages[1].mutable_login()->set_password("lovelace1");
  messages[2].mutable_resume()->set_session_token(std::string(64, 'f'));
  messages[3].mutable_list_matches();
  messages[4].mutable_create_match()->set_name("duel");
  messages[4].mutable_create_match()->set_max_players(2);
  messages[4].mutable_create_match()->set_map("arena");
  messages[5].mutable_join_match()->set_match_id(1);
  messages[6].mutable_leave_match();
  messages[7].mutable_chat()->set_text("gl hf");
  messages[8].mutable_ping()->set_client_time_us(123456789);
  for (std::size_t i = 0; i < messages.size(); ++i) {
    messages[i].set_request_id(static_cast<std::uint32_t>(i + 1));
  }
  return messages;
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
    std::fprintf(stderr, "usage: control_frame_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = true;
  std::vector<std::uint8_t> all;
  const auto messages = one_of_each();
  for (std::size_t i = 0; i < messages.size(); ++i) {
    std::vector<std::uint8_t> one;
    ok &= ricochet::proto::append_frame(messages[i], one);
    ok &= write(dir, "kind" + std::to_string(i), 255, one);
    ok &= ricochet::proto::append_frame(messages[i], all);
  }
  ok &= write(dir, "pipelined_whole", 255, all);
  ok &= write(dir, "pipelined_bytewise", 0, all);
  ok &= write(dir, "pipelined_chunks7", 6, all);
  ok &= write(dir, "oversize", 255, {0x00, 0x01, 0x00, 0x01});
  ok &= write(dir, "empty", 255, {0x00, 0x00, 0x00, 0x00});
  ok &= write(dir, "garbage", 255, {0x00, 0x00, 0x00, 0x05, 0xff, 0xff, 0xff, 0xff, 0x0f});
  ok &= write(dir, "no_body", 255, {0x00, 0x00, 0x00, 0x02, 0x08, 0x07});
  ok &= write(dir, "bad_utf8", 255,
              {0x00, 0x00, 0x00, 0x08, 0x08, 0x01, 0x1a, 0x04, 0x0a, 0x02, 0xff, 0xfe});
  ok &= write(dir, "partial", 3, {0x00, 0x00, 0x00, 0x20, 0x08, 0x01});
  if (!ok) {
    std::fprintf(stderr, "control_frame_seeds: cannot write the seeds into %s\n", dir.c_str());
    return 1;
  }
  return 0;
}
