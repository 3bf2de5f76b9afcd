// libFuzzer target for decode_outbox_record (server/src/net/results_outbox_format.cpp), the
// reader of the files a server left in its results outbox. The first input byte picks a mode:
// even, the rest is read as it is (the CRC-32 must check); odd, the fuzzer first rewrites the
// header's length and CRC-32 to fit the bytes, so the mutations reach the payload's decoder. Any
// bytes are either refused with a reason or read into a record that, encoded again, gives the
// same bytes. Every other outcome, and every sanitizer report, is a bug. Run it with
// tools/fuzz.sh --only results_outbox.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include "../../server/src/match/recording_format.h"
#include "results_outbox_format.h"

namespace {

using namespace ricochet::server;

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "results_outbox_fuzz: %s\n", what);
  std::abort();
}

void store32(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

/// The header's length and CRC-32 made to fit what follows it.
void repair_header(std::vector<std::uint8_t>& bytes) {
  if (bytes.size() < kOutboxHeaderBytes) return;
  const auto payload = std::span(bytes).subspan(kOutboxHeaderBytes);
  store32(bytes, 10, static_cast<std::uint32_t>(payload.size()));
  store32(bytes, 14, recording_format::crc32(payload));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if (data[0] & 1) repair_header(bytes);
  const DecodedOutbox decoded = decode_outbox_record(bytes);
  if (!decoded.ok) {
    check(!decoded.problem.empty(), "a refusal without a reason");
    return 0;
  }
  check(decoded.problem.empty(), "a record with a refusal");
  check(!decoded.record.record.players.empty(), "a record without players");
  check(encode_outbox_record(decoded.record) == bytes, "a record does not encode back the same");
  return 0;
}
