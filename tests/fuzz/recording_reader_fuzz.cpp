// libFuzzer target for read_recording (server/src/match/recording_reader.cpp). The first input
// byte picks a mode: even, the rest is read as it is (every frame and the footer must check);
// odd, the fuzzer first rewrites every chunk's CRC-32s and the footer's file checksum, so the
// mutations reach the decoder behind them. Any bytes are either refused with a RecordingError or
// read into a recording that keeps the rules (increasing ticks, at most 64 distinct inputs per
// tick, every value in range, hashes on recorded ticks) and that, written again by
// RecordingWriter, reads back the same. Every other outcome, and every sanitizer report, is a
// bug. Run it with tools/fuzz.sh --only recording_reader.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <variant>
#include <vector>

#include "../../server/src/match/recording_format.h"
#include "ricochet/server/recording.h"

namespace {

using namespace ricochet::server;
namespace rf = recording_format;

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "recording_reader_fuzz: %s\n", what);
  std::abort();
}

std::uint32_t le32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= std::uint32_t{bytes[at + i]} << (8 * i);
  return value;
}

void store32(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

/// Rewrites the frame and payload CRC-32s of every whole chunk, and the footer's file CRC.
void repair_checksums(std::vector<std::uint8_t>& bytes) {
  std::size_t pos = rf::kMagic.size() + 1;
  while (pos + rf::kFrameHeadBytes <= bytes.size()) {
    const std::uint32_t length = le32(bytes, pos + 1);
    store32(bytes, pos + 5, rf::crc32(std::span(bytes).subspan(pos, 5)));
    const std::size_t payload = pos + rf::kFrameHeadBytes;
    if (bytes.size() - payload < std::size_t{length} + 4) return;
    if (bytes[pos] == rf::kChunkFooter && length >= 4) {
      store32(bytes, payload + length - 4, rf::crc32(std::span(bytes).first(pos)));
    }
    store32(bytes, payload + length, rf::crc32(std::span(bytes).subspan(payload, length)));
    pos = payload + length + 4;
  }
}

void check_rules(const Recording& recording) {
  check(rf::check_header(recording.header).empty(), "accepted header breaks a cap");
  // A cut file says where it stops, within the file; a whole one says nothing.
  check(recording.complete == recording.cut.empty(), "a cut file without its statement");
  check(recording.complete || recording.cut.find("replayable to tick") != std::string::npos,
        "a cut statement without the last tick");
  std::uint32_t last = 0;
  std::size_t hash = 0;
  for (const RecordedTick& tick : recording.ticks) {
    check(tick.tick > last, "ticks do not increase");
    last = tick.tick;
    check(tick.inputs.size() <= kMaxRecordedPlayers, "more than 64 inputs in a tick");
    check(tick.events.size() <= kMaxRecordedEventsPerTick, "too many events in a tick");
    for (const RecordedEvent& event : tick.events) {
      check(rf::check_event(event).empty(), "accepted event is invalid");
    }
    for (std::size_t i = 0; i < tick.inputs.size(); ++i) {
      check(rf::check_input(tick.inputs[i].input).empty(), "accepted input out of range");
      for (std::size_t j = 0; j < i; ++j) {
        check(tick.inputs[i].entity_id != tick.inputs[j].entity_id, "an entity twice in a tick");
      }
    }
    while (hash < recording.hashes.size() && recording.hashes[hash].tick == tick.tick) ++hash;
    check(hash == recording.hashes.size() || recording.hashes[hash].tick > tick.tick,
          "a hash on a tick that is not recorded, or out of order");
  }
  check(hash == recording.hashes.size(), "a hash after the last tick");
  check(recording.complete || !recording.players, "a player count without a footer");
  for (std::size_t i = 1; i < recording.hashes.size(); ++i) {
    check(recording.hashes[i].tick > recording.hashes[i - 1].tick, "two hashes for one tick");
  }
}

void check_rewrite(const Recording& recording) {
  RecordingWriter writer(recording.header, kMaxRecordingBytes);
  std::size_t hash = 0;
  for (const RecordedTick& tick : recording.ticks) {
    writer.begin_tick(tick.tick);
    for (const RecordedEvent& event : tick.events) writer.add_event(event);
    for (const RecordedInput& input : tick.inputs) writer.add_input(input);
    writer.end_tick();
    if (hash < recording.hashes.size() && recording.hashes[hash].tick == tick.tick) {
      writer.add_hash(tick.tick, recording.hashes[hash++].hash);
    }
  }
  check(writer.stopped_reason().empty(), "the writer refused an accepted recording");
  const auto bytes = writer.finish();
  const auto again = read_recording(bytes);
  const auto* back = std::get_if<Recording>(&again);
  check(back != nullptr, "a rewritten recording does not read");
  check(back->complete && !back->truncated, "a rewritten recording is not complete");
  check(back->ticks.size() == recording.ticks.size(), "rewrite changed the tick count");
  check(back->hashes.size() == recording.hashes.size(), "rewrite changed the hash count");
  check(back->players.has_value(), "a rewritten footer without its player count");
  check(!recording.players || back->players == recording.players,
        "rewrite changed the player count");
  for (std::size_t i = 0; i < back->ticks.size(); ++i) {
    const RecordedTick& a = recording.ticks[i];
    const RecordedTick& b = back->ticks[i];
    check(a.tick == b.tick && a.inputs.size() == b.inputs.size() &&
              a.events.size() == b.events.size(),
          "rewrite changed a tick");
    for (std::size_t j = 0; j < a.inputs.size(); ++j)
      check(bit_identical(a.inputs[j], b.inputs[j]), "rewrite changed an input");
    for (std::size_t j = 0; j < a.events.size(); ++j) {
      check(a.events[j].kind == b.events[j].kind && a.events[j].account == b.events[j].account &&
                a.events[j].name == b.events[j].name &&
                a.events[j].end_reason == b.events[j].end_reason,
            "rewrite changed an event");
    }
  }
  for (std::size_t i = 0; i < back->hashes.size(); ++i) {
    check(back->hashes[i].tick == recording.hashes[i].tick &&
              back->hashes[i].hash == recording.hashes[i].hash,
          "rewrite changed a hash");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if (data[0] & 1) repair_checksums(bytes);
  const auto result = read_recording(bytes);
  if (const auto* error = std::get_if<RecordingError>(&result)) {
    check(!error->message.empty(), "an error without a message");
    check(error->offset <= bytes.size(), "an error offset past the end");
    return 0;
  }
  const Recording& recording = std::get<Recording>(result);
  check_rules(recording);
  check(recording.cut_offset <= bytes.size(), "a cut offset past the end");
  check_rewrite(recording);
  return 0;
}
