// libFuzzer target for the control channel's frame reader and ClientMessage parser: the input
// is a byte stream a client might send over TLS, fed in chunks whose sizes come from the input
// itself. Nothing may crash; a refused stream stays refused; every parsed message re-encodes
// to a frame that parses to the same message.

#include <google/protobuf/stubs/logging.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "fuzz_check.h"
#include "ricochet/proto/control_states.h"
#include "ricochet/proto/frame.h"

namespace {

using namespace ricochet::proto;

using ricochet::fuzz::check;

void check_message(const std::vector<std::uint8_t>& payload) {
  ricochet::wire::ClientMessage message;
  if (parse_client_message(payload, message)) return;
  const ClientMessageKind kind = kind_of(message);
  for (std::size_t s = 0; s < kControlStateCount; ++s) {
    (void)admits(static_cast<ControlState>(s), kind);
  }
  std::vector<std::uint8_t> again;
  check(append_frame(message, again) || message.ByteSizeLong() > kMaxFramePayloadBytes);
  if (again.empty()) return;
  FrameReader reader;
  reader.feed(again);
  std::vector<std::uint8_t> reparsed_payload;
  check(reader.next(reparsed_payload) == FrameReader::Status::Frame);
  ricochet::wire::ClientMessage reparsed;
  check(!parse_client_message(reparsed_payload, reparsed));
  check(reparsed.SerializeAsString() == message.SerializeAsString());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  google::protobuf::SetLogHandler(nullptr);  // invalid UTF-8 is expected here, not news
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  // First byte: the chunk size pattern (1..256 bytes per feed).
  const std::size_t chunk = std::size_t{data[0]} + 1;
  const std::span<const std::uint8_t> stream(data + 1, size - 1);
  FrameReader reader;
  std::vector<std::uint8_t> payload;
  bool refused = false;
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    reader.feed(stream.subspan(at, std::min(chunk, stream.size() - at)));
    while (true) {
      const FrameReader::Status status = reader.next(payload);
      if (status == FrameReader::Status::NeedMore) break;
      if (status == FrameReader::Status::Refused) {
        check(reader.refusal().has_value());
        check(reader.buffered() == 0);
        refused = true;
        break;
      }
      check(!refused);
      check(!payload.empty() && payload.size() <= kMaxFramePayloadBytes);
      check_message(payload);
    }
    check(reader.buffered() <= kFrameHeaderBytes + kMaxFramePayloadBytes);
  }
  return 0;
}
