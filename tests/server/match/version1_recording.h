#pragma once
/// A recording as the version 1 writer wrote it, for the tests that old files still read: the
/// same bytes with version byte 1 and a footer without the player count (server/RECORDING.md,
/// Versions).

#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "recording_format.h"
#include "ricochet/server/recording.h"

namespace ricochet::server::recording_test {

/// `bytes`, a whole recording written by RecordingWriter, rewritten as version 1.
inline std::vector<std::uint8_t> as_version_1(std::vector<std::uint8_t> bytes) {
  namespace rf = recording_format;
  const auto read = read_recording(bytes);
  const Recording* recording = std::get_if<Recording>(&read);
  EXPECT_TRUE(recording && recording->complete) << "a whole recording to rewrite";
  if (!recording || !recording->complete) return {};
  std::uint64_t events = 0, inputs = 0, chunks = 0;
  std::size_t pos = rf::kMagic.size() + 1;
  while (bytes[pos] != rf::kChunkFooter) {
    std::uint32_t length = 0;
    for (int i = 0; i < 4; ++i) length |= std::uint32_t{bytes[pos + 1 + i]} << (8 * i);
    chunks += bytes[pos] == rf::kChunkTicks ? 1 : 0;
    pos += rf::kFrameBytes + length;
  }
  for (const RecordedTick& tick : recording->ticks) {
    events += tick.events.size();
    inputs += tick.inputs.size();
  }
  const std::uint32_t last_tick = recording->ticks.empty() ? 0 : recording->ticks.back().tick;
  const bool truncated = recording->truncated;
  const std::size_t ticks = recording->ticks.size(), hashes = recording->hashes.size();
  bytes.resize(pos);
  bytes[rf::kMagic.size()] = 1;
  std::vector<std::uint8_t> footer;
  for (const std::uint64_t total : {std::uint64_t{ticks}, events, inputs, std::uint64_t{hashes},
                                    std::uint64_t{last_tick}, chunks}) {
    rf::put_varint(footer, total);
  }
  footer.push_back(truncated ? 1 : 0);
  rf::put_u32(footer, rf::crc32(bytes));
  rf::put_chunk(bytes, rf::kChunkFooter, footer);
  return bytes;
}

}  // namespace ricochet::server::recording_test
