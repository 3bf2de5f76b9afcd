// Match recordings (recording.h): bit-exact round trips, every corruption and truncation caught,
// the size bound, and the size per player-minute of a scripted 60 Hz input stream.

#include "ricochet/server/recording.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "recording_format.h"
#include "version1_recording.h"

namespace ricochet::server::recording_test {
namespace {

namespace rf = recording_format;

/// text + the number (gcc 12 warns falsely on a literal + std::to_string()).
std::string with_number(const char* text, std::uint64_t number) {
  std::string out = text;
  out += std::to_string(number);
  return out;
}

bool same_event(const RecordedEvent& a, const RecordedEvent& b) {
  return a.kind == b.kind && a.account == b.account && a.name == b.name &&
         a.end_reason == b.end_reason;
}

bool same_tick(const RecordedTick& a, const RecordedTick& b) {
  if (a.tick != b.tick || a.events.size() != b.events.size() ||
      a.inputs.size() != b.inputs.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    if (!same_event(a.events[i], b.events[i])) return false;
  }
  for (std::size_t i = 0; i < a.inputs.size(); ++i) {
    if (!bit_identical(a.inputs[i], b.inputs[i])) return false;
  }
  return true;
}

void expect_same_header(const RecordingHeader& a, const RecordingHeader& b) {
  EXPECT_EQ(a.server_version, b.server_version);
  ASSERT_EQ(a.map_files.size(), b.map_files.size());
  for (std::size_t i = 0; i < a.map_files.size(); ++i) {
    EXPECT_EQ(a.map_files[i].path, b.map_files[i].path);
    EXPECT_EQ(a.map_files[i].text, b.map_files[i].text);
  }
  EXPECT_EQ(a.config, b.config);
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_EQ(a.hash_interval_ticks, b.hash_interval_ticks);
  EXPECT_EQ(a.tick_rate_hz, b.tick_rate_hz);
}

/// `prefix` ticks and hashes of `expected` equal `got`'s (all of them when complete).
void expect_prefix(const Recording& expected, const Recording& got) {
  expect_same_header(expected.header, got.header);
  ASSERT_LE(got.ticks.size(), expected.ticks.size());
  for (std::size_t i = 0; i < got.ticks.size(); ++i) {
    ASSERT_TRUE(same_tick(expected.ticks[i], got.ticks[i])) << "tick index " << i;
  }
  ASSERT_LE(got.hashes.size(), expected.hashes.size());
  for (std::size_t i = 0; i < got.hashes.size(); ++i) {
    EXPECT_EQ(expected.hashes[i].tick, got.hashes[i].tick);
    EXPECT_EQ(expected.hashes[i].hash, got.hashes[i].hash);
  }
}

RecordingHeader sample_header() {
  RecordingHeader header;
  header.server_version = "0.1.0-test";
  header.map_files = {{"server/maps/arena.toml", "name = \"arena\"\n"},
                      {"server/maps/ramps.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n"}};
  header.config = {1, 2, 3, 0, 255};
  header.seed = 0xDEADBEEFCAFEF00Dull;
  header.hash_interval_ticks = 10;
  header.tick_rate_hz = 60;
  return header;
}

/// A random but valid recording: players join, move, fire, leave, come back with a new sequence.
Recording random_recording(std::uint32_t seed, int ticks) {
  std::mt19937 rng(seed);
  const auto chance = [&](double p) {
    return std::uniform_real_distribution<double>(0, 1)(rng) < p;
  };
  const auto steps = [&] { return std::uniform_int_distribution<int>(-127, 127)(rng); };
  Recording recording;
  recording.header = sample_header();
  recording.header.seed = seed;
  recording.complete = true;
  std::vector<RecordedInput> players;
  std::uint32_t next_entity = 1;
  std::uint32_t tick = 0;
  for (int i = 0; i < ticks; ++i) {
    tick += chance(0.05) ? 1 + static_cast<std::uint32_t>(rng() % 200) : 1;
    RecordedTick record;
    record.tick = tick;
    if (chance(0.03) && players.size() < kMaxRecordedPlayers) {
      RecordedInput player;
      player.entity_id = next_entity++;
      players.push_back(player);
      record.events.push_back({RecordedEventKind::Connect, 1000 + player.entity_id,
                               with_number("player", player.entity_id), 0});
    }
    if (chance(0.01) && !players.empty()) {
      const std::size_t gone = rng() % players.size();
      const auto kind = static_cast<RecordedEventKind>(2 + rng() % 3);
      record.events.push_back({kind, 1000 + players[gone].entity_id, "", 0});
      players.erase(players.begin() + static_cast<std::ptrdiff_t>(gone));
    }
    if (chance(0.005)) record.events.push_back({RecordedEventKind::End, 0, "", 2});
    for (RecordedInput& player : players) {
      PlayerInput& in = player.input;
      in.sequence = chance(0.01) ? static_cast<std::uint32_t>(rng() % 5) : in.sequence + 1;
      if (chance(0.2)) {
        in.move_right = static_cast<float>(steps()) / proto::kMoveSteps;
        in.move_forward = static_cast<float>(steps()) / proto::kMoveSteps;
        const float length =
            std::sqrt(in.move_right * in.move_right + in.move_forward * in.move_forward);
        if (length > 1) {
          in.move_right /= length;
          in.move_forward /= length;
        }
      }
      if (chance(0.7)) in.yaw_rad = std::uniform_real_distribution<float>(-6.28f, 6.28f)(rng);
      if (chance(0.01)) in.yaw_rad = -0.0f;
      if (chance(0.3)) in.pitch_rad = std::uniform_real_distribution<float>(-1.57f, 1.57f)(rng);
      if (chance(0.1)) in.buttons = static_cast<std::uint32_t>(rng() % 8);
      if (chance(0.02)) in.weapon_slot = static_cast<std::uint32_t>(rng() % 10);
      in.view_tick = chance(0.05) ? static_cast<std::uint32_t>(rng() % (tick + 1))
                                  : (in.view_tick == 0 ? 0 : in.view_tick + 1);
      if (chance(0.5)) in.view_fraction = static_cast<std::uint8_t>(rng());
      if (chance(0.1)) player.latency_us = static_cast<std::uint32_t>(rng() % 200'000);
      if (chance(0.98)) record.inputs.push_back(player);  // a player may miss a tick's input
    }
    if (chance(0.2) && record.inputs.size() > 1) std::swap(record.inputs[0], record.inputs[1]);
    if (tick % recording.header.hash_interval_ticks == 0 || chance(0.01)) {
      recording.hashes.push_back({tick, (std::uint64_t{rng()} << 32) | rng()});
    }
    recording.ticks.push_back(std::move(record));
  }
  return recording;
}

/// Writes one tick of `recording`, then the hash recorded at it if `next_hash` names one.
void write_tick(RecordingWriter& writer, const Recording& recording, const RecordedTick& tick,
                std::size_t& next_hash) {
  writer.begin_tick(tick.tick);
  for (const RecordedEvent& event : tick.events) writer.add_event(event);
  for (const RecordedInput& input : tick.inputs) writer.add_input(input);
  writer.end_tick();
  if (next_hash < recording.hashes.size() && recording.hashes[next_hash].tick == tick.tick) {
    writer.add_hash(tick.tick, recording.hashes[next_hash++].hash);
  }
}

std::vector<std::uint8_t> write(const Recording& recording, std::size_t max_bytes = 64u << 20) {
  RecordingWriter writer(recording.header, max_bytes);
  std::size_t next_hash = 0;
  for (const RecordedTick& tick : recording.ticks) write_tick(writer, recording, tick, next_hash);
  EXPECT_TRUE(writer.stopped_reason().empty() || max_bytes < (64u << 20))
      << writer.stopped_reason();
  return writer.finish();
}

Recording read_ok(const std::vector<std::uint8_t>& bytes) {
  auto result = read_recording(bytes);
  if (const auto* error = std::get_if<RecordingError>(&result)) {
    ADD_FAILURE() << "read_recording: " << error->message;
    return {};
  }
  return std::get<Recording>(std::move(result));
}

/// Where each chunk of a valid file starts, and its end.
std::vector<std::size_t> chunk_starts(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::size_t> starts;
  std::size_t pos = rf::kMagic.size() + 1;
  while (pos < bytes.size()) {
    starts.push_back(pos);
    std::uint32_t length = 0;
    for (int i = 0; i < 4; ++i) length |= std::uint32_t{bytes[pos + 1 + i]} << (8 * i);
    pos += rf::kFrameBytes + length;
  }
  starts.push_back(pos);
  return starts;
}

TEST(RecordingTest, RandomRecordingsRoundTripBitExactly) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const Recording recording = random_recording(seed, 1500);
    const auto bytes = write(recording);
    const Recording back = read_ok(bytes);
    EXPECT_TRUE(back.complete);
    EXPECT_FALSE(back.truncated);
    EXPECT_EQ(back.ticks.size(), recording.ticks.size()) << "seed " << seed;
    EXPECT_EQ(back.hashes.size(), recording.hashes.size()) << "seed " << seed;
    expect_prefix(recording, back);
  }
}

TEST(RecordingTest, EmptyRecordingRoundTrips) {
  RecordingHeader header;
  header.tick_rate_hz = 128;
  RecordingWriter writer(header, 1024);
  const auto bytes = writer.finish();
  const Recording back = read_ok(bytes);
  EXPECT_TRUE(back.complete);
  EXPECT_TRUE(back.ticks.empty());
  EXPECT_EQ(back.header.tick_rate_hz, 128u);
  EXPECT_TRUE(writer.finish().empty()) << "a second finish() returns nothing";
}

TEST(RecordingTest, QuietTicksCostOneByte) {
  Recording recording;
  recording.header = sample_header();
  for (std::uint32_t t = 1; t <= 1001; ++t) {
    RecordedTick tick;
    tick.tick = t;
    RecordedInput input;
    input.entity_id = 7;
    input.input.sequence = t;
    tick.inputs.push_back(input);
    recording.ticks.push_back(tick);
  }
  Recording first;
  first.header = recording.header;
  first.ticks = {recording.ticks[0]};
  const std::size_t one = write(first).size();
  const std::size_t all = write(recording).size();
  EXPECT_LE(all - one, 1000u + 8) << "1000 ticks of one player repeating its input";
  expect_prefix(recording, read_ok(write(recording)));
}

TEST(RecordingTest, HashForALaterTickBecomesATickOfItsOwn) {
  RecordingWriter writer(sample_header(), 1 << 20);
  writer.begin_tick(1);
  writer.end_tick();
  writer.add_hash(5, 42);
  const Recording back = read_ok(writer.finish());
  ASSERT_EQ(back.ticks.size(), 2u);
  EXPECT_EQ(back.ticks[1].tick, 5u);
  ASSERT_EQ(back.hashes.size(), 1u);
  EXPECT_EQ(back.hashes[0].tick, 5u);
  EXPECT_EQ(back.hashes[0].hash, 42u);
}

TEST(RecordingTest, EverySingleBitFlipIsAnErrorNamingItsChunk) {
  const auto bytes = write(random_recording(7, 300));
  const auto starts = chunk_starts(bytes);
  ASSERT_GE(starts.size(), 4u) << "header, ticks, footer";
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    auto broken = bytes;
    broken[at] ^= static_cast<std::uint8_t>(1u << (at % 8));
    const auto result = read_recording(broken);
    const auto* error = std::get_if<RecordingError>(&result);
    ASSERT_NE(error, nullptr) << "a flipped bit in byte " << at << " went unnoticed";
    if (at < starts.front()) continue;  // magic and version
    std::size_t chunk = 0;
    while (starts[chunk + 1] <= at) ++chunk;
    const std::string name = with_number("chunk ", chunk);
    EXPECT_NE(error->message.find(name), std::string::npos)
        << "byte " << at << ": " << error->message;
    EXPECT_NE(error->message.find("CRC-32 mismatch"), std::string::npos) << error->message;
  }
}

TEST(RecordingTest, TruncationIsAnErrorInTheHeaderAndAPrefixAfterIt) {
  const Recording recording = random_recording(11, 500);
  const auto bytes = write(recording);
  const auto starts = chunk_starts(bytes);
  ASSERT_GE(starts.size(), 5u) << "more than one tick chunk";
  const std::size_t header_end = starts[1];
  std::size_t incomplete = 0;
  // Every byte through the header and the start of the first tick chunk and around every
  // chunk boundary, every 97th byte elsewhere (reading is linear in the size).
  const auto near_boundary = [&](std::size_t cut) {
    for (const std::size_t start : starts) {
      if (cut + 24 >= start && cut <= start + 24) return true;
    }
    return cut < header_end + 2048;
  };
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    if (!near_boundary(cut) && cut % 97 != 0) continue;
    const std::vector<std::uint8_t> part(bytes.begin(),
                                         bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    const auto result = read_recording(part);
    if (cut < header_end) {
      const auto* error = std::get_if<RecordingError>(&result);
      ASSERT_NE(error, nullptr) << "cut at " << cut;
      EXPECT_NE(error->message.find(with_number("truncated at byte ", cut)), std::string::npos)
          << error->message;
      continue;
    }
    const auto* got = std::get_if<Recording>(&result);
    ASSERT_NE(got, nullptr) << "cut at " << cut << ": " << std::get<RecordingError>(result).message;
    EXPECT_FALSE(got->complete);
    expect_prefix(recording, *got);
    if (cut == starts[starts.size() - 2]) {
      EXPECT_EQ(got->ticks.size(), recording.ticks.size()) << "only the footer is missing";
    }
    ++incomplete;
  }
  EXPECT_GT(incomplete, 0u);
}

TEST(RecordingTest, TakingCompletedChunksAsTheyComeGivesTheSameFile) {
  // The server streams each completed chunk to disk: those pieces and finish() are the file
  // finish() alone returns, byte for byte.
  const Recording recording = random_recording(5, 3000);
  const auto whole = write(recording);
  RecordingWriter writer(recording.header, 64u << 20);
  std::vector<std::uint8_t> streamed = writer.take_completed();
  const std::size_t header_end = chunk_starts(whole)[1];
  EXPECT_EQ(streamed.size(), header_end) << "the magic and the header come first";
  std::size_t next_hash = 0;
  std::size_t pieces = 0;
  for (const RecordedTick& tick : recording.ticks) {
    write_tick(writer, recording, tick, next_hash);
    const auto piece = writer.take_completed();
    if (piece.empty()) continue;
    ++pieces;
    streamed.insert(streamed.end(), piece.begin(), piece.end());
    EXPECT_EQ(read_ok(streamed).cut.find("ends after chunk"), 0u) << "whole chunks only";
  }
  EXPECT_TRUE(writer.take_completed().empty());
  const auto rest = writer.finish();
  streamed.insert(streamed.end(), rest.begin(), rest.end());
  EXPECT_GE(pieces, 3u);
  EXPECT_EQ(streamed, whole);
}

TEST(RecordingTest, EveryCutOfASmallRecordingReadsToItsLastWholeChunkOrIsRefused) {
  const Recording recording = random_recording(13, 450);
  const auto bytes = write(recording);
  const auto starts = chunk_starts(bytes);
  ASSERT_GE(starts.size(), 5u) << "header, two tick chunks, footer";
  // What each whole prefix up to a chunk boundary holds.
  std::vector<std::size_t> ticks_before(starts.size());
  for (std::size_t i = 1; i < starts.size(); ++i) {
    const Recording upto = read_ok({bytes.begin(), bytes.begin() + starts[i]});
    ticks_before[i] = upto.ticks.size();
  }
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    const std::span<const std::uint8_t> part(bytes.data(), cut);
    const auto result = read_recording(part);
    if (cut < starts[1]) {
      const auto* error = std::get_if<RecordingError>(&result);
      ASSERT_NE(error, nullptr) << "cut at " << cut << " inside the header";
      EXPECT_NE(error->message.find(with_number("truncated at byte ", cut)), std::string::npos)
          << error->message;
      continue;
    }
    const auto* got = std::get_if<Recording>(&result);
    ASSERT_NE(got, nullptr) << "cut at " << cut << ": " << std::get<RecordingError>(result).message;
    std::size_t chunk = 1;  // the chunk the cut falls in (or the one it ends before)
    while (starts[chunk + 1] <= cut) ++chunk;
    EXPECT_FALSE(got->complete);
    EXPECT_EQ(got->ticks.size(), ticks_before[chunk]) << "cut at " << cut;
    EXPECT_EQ(got->cut_offset, starts[chunk]);
    const std::uint32_t last = got->ticks.empty() ? 0 : got->ticks.back().tick;
    const std::string replayable = with_number("replayable to tick ", last);
    EXPECT_NE(got->cut.find(replayable), std::string::npos) << got->cut;
    const std::string at = with_number(" at byte ", starts[chunk]);
    EXPECT_NE(got->cut.find(at), std::string::npos) << got->cut;
    if (cut == starts[chunk]) {
      EXPECT_EQ(got->cut.find(with_number("ends after chunk ", chunk - 1)), 0u) << got->cut;
    } else {
      EXPECT_EQ(got->cut.find(with_number("cut inside chunk ", chunk)), 0u) << got->cut;
    }
    expect_prefix(recording, *got);
  }
  const Recording whole = read_ok(bytes);
  EXPECT_TRUE(whole.complete);
  EXPECT_TRUE(whole.cut.empty());
}

TEST(RecordingTest, AListingReadsTheHeaderAndTheFooterAloneAndNoFooterInACutFile) {
  const Recording recording = random_recording(21, 450);
  const auto bytes = write(recording);
  const auto starts = chunk_starts(bytes);
  // The header from the first bytes: as many as the first 13 say, and no more needed.
  const auto needed = recording_header_bytes(std::span(bytes).first(14));
  ASSERT_TRUE(std::holds_alternative<std::size_t>(needed));
  ASSERT_EQ(std::get<std::size_t>(needed), starts[1]);
  const auto header = read_recording_header(std::span(bytes).first(starts[1]));
  ASSERT_TRUE(std::holds_alternative<RecordingHeader>(header));
  EXPECT_EQ(std::get<RecordingHeader>(header).seed, recording.header.seed);
  EXPECT_EQ(std::get<RecordingHeader>(header).map_files.size(), recording.header.map_files.size());
  const auto short_header = read_recording_header(std::span(bytes).first(starts[1] - 1));
  ASSERT_TRUE(std::holds_alternative<RecordingError>(short_header));
  EXPECT_NE(std::get<RecordingError>(short_header).message.find("(expected 1 more bytes)"),
            std::string::npos);
  // The footer from the last bytes: the totals read_recording() checks.
  const auto footer = read_recording_footer(
      std::span(bytes).last(std::min(bytes.size(), kMaxRecordingFooterBytes)));
  ASSERT_TRUE(footer.has_value());
  EXPECT_EQ(footer->ticks, recording.ticks.size());
  EXPECT_EQ(footer->last_tick, recording.ticks.back().tick);
  EXPECT_EQ(footer->hashes, recording.hashes.size());
  EXPECT_EQ(footer->tick_chunks, starts.size() - 3);
  EXPECT_FALSE(footer->truncated);
  // No cut file ends with one, whatever its last bytes (a cut inside the footer included).
  for (std::size_t cut = starts[1]; cut < bytes.size(); ++cut) {
    const std::span<const std::uint8_t> part(bytes.data(), cut);
    EXPECT_FALSE(read_recording_footer(part.last(std::min(cut, kMaxRecordingFooterBytes))))
        << "cut at " << cut;
  }
  // Nor a footer whose bytes were changed.
  for (std::size_t at = starts[starts.size() - 2]; at < bytes.size(); ++at) {
    std::vector<std::uint8_t> flipped = bytes;
    flipped[at] ^= 0x01;
    EXPECT_FALSE(read_recording_footer(std::span(flipped).last(kMaxRecordingFooterBytes))) << at;
  }
}

/// A recording of `ticks` ticks, one player's input each, with `events` at the ticks they name.
Recording with_events(std::uint32_t ticks,
                      const std::vector<std::pair<std::uint32_t, RecordedEvent>>& events) {
  Recording recording;
  recording.header = sample_header();
  for (std::uint32_t t = 1; t <= ticks; ++t) {
    RecordedTick tick;
    tick.tick = t;
    for (const auto& [at, event] : events) {
      if (at == t) tick.events.push_back(event);
    }
    RecordedInput input;
    input.entity_id = 1;
    input.input.sequence = t;
    input.input.yaw_rad = 0.001f * static_cast<float>(t);  // 4 bytes a tick
    tick.inputs.push_back(input);
    recording.ticks.push_back(std::move(tick));
  }
  return recording;
}

RecordedEvent connect(std::uint64_t account) {
  return {RecordedEventKind::Connect, account, with_number("p", account), 0};
}

RecordedEvent gone(RecordedEventKind kind, std::uint64_t account) {
  return {kind, account, "", 0};
}

TEST(RecordingTest, TheFooterCountsTheDistinctAccountsThatConnected) {
  using K = RecordedEventKind;
  const struct {
    const char* what;
    std::vector<std::pair<std::uint32_t, RecordedEvent>> events;
    std::uint32_t players;
  } cases[] = {
      {"nobody", {{5, {K::End, 0, "", 2}}}, 0},
      {"one", {{1, connect(7)}}, 1},
      {"several", {{1, connect(7)}, {1, connect(8)}, {3, connect(9)}, {4, gone(K::Leave, 8)}}, 3},
      {"reconnects",
       {{1, connect(7)},
        {2, connect(8)},
        {3, gone(K::Disconnect, 7)},
        {5, connect(7)},  // back within the grace
        {6, gone(K::Leave, 8)},
        {8, connect(8)},  // left, then joined again
        {9, gone(K::TimedOut, 7)},
        {10, connect(7)}},
       2},
  };
  for (const auto& c : cases) {
    const auto bytes = write(with_events(12, c.events));
    const Recording back = read_ok(bytes);
    EXPECT_EQ(back.players, c.players) << c.what;
    const auto footer = read_recording_footer(std::span(bytes).last(kMaxRecordingFooterBytes));
    ASSERT_TRUE(footer.has_value()) << c.what;
    EXPECT_EQ(footer->players, c.players) << c.what;
  }
}

TEST(RecordingTest, AStoppedWriterCountsThePlayersItRecorded) {
  // Account 7 joins at tick 1, account 8 at tick 400: past the limit.
  const Recording recording = with_events(400, {{1, connect(7)}, {400, connect(8)}});
  const auto whole = write(recording);
  const auto bytes = write(recording, whole.size() / 2);
  const Recording back = read_ok(bytes);
  ASSERT_TRUE(back.truncated);
  EXPECT_EQ(back.players, 1u);
  EXPECT_EQ(read_ok(whole).players, 2u);
}

TEST(RecordingTest, AVersion1FileReadsWithItsPlayersUnknown) {
  const Recording recording = with_events(40, {{1, connect(7)}, {2, connect(8)}});
  EXPECT_EQ(read_ok(write(recording)).players, 2u) << "written now: counted";
  const auto bytes = as_version_1(write(recording));
  ASSERT_EQ(bytes[8], 1);
  const Recording back = read_ok(bytes);
  EXPECT_TRUE(back.complete);
  EXPECT_FALSE(back.players.has_value());
  EXPECT_EQ(back.ticks.size(), 40u);
  expect_prefix(recording, back);
  const auto needed = recording_header_bytes(std::span(bytes).first(14));
  ASSERT_TRUE(std::holds_alternative<std::size_t>(needed));
  EXPECT_TRUE(std::holds_alternative<RecordingHeader>(
      read_recording_header(std::span(bytes).first(std::get<std::size_t>(needed)))));
  const auto footer = read_recording_footer(std::span(bytes).last(kMaxRecordingFooterBytes));
  ASSERT_TRUE(footer.has_value());
  EXPECT_EQ(footer->ticks, 40u);
  EXPECT_EQ(footer->events, 2u);
  EXPECT_FALSE(footer->players.has_value());
}

TEST(RecordingTest, ACorruptChunkBeforeACutIsStillAnError) {
  // A cut file is read up to the cut, but bad bytes in the middle are still refused.
  const auto bytes = write(random_recording(17, 600));
  const auto starts = chunk_starts(bytes);
  ASSERT_GE(starts.size(), 5u);
  std::vector<std::uint8_t> part(bytes.begin(), bytes.begin() + starts[3] + 5);
  part[starts[2] + 20] ^= 0x40;
  const auto result = read_recording(part);
  const auto* error = std::get_if<RecordingError>(&result);
  ASSERT_NE(error, nullptr);
  EXPECT_NE(error->message.find("chunk 2 (ticks)"), std::string::npos) << error->message;
  EXPECT_NE(error->message.find("CRC-32 mismatch"), std::string::npos) << error->message;
}

TEST(RecordingTest, WriterStopsAtMaxBytesAndTheFileSaysSo) {
  const Recording recording = random_recording(3, 3000);
  const std::size_t whole = write(recording).size();
  for (const std::size_t max : {whole / 2, whole / 5, std::size_t{700}}) {
    RecordingWriter writer(recording.header, max);
    for (const RecordedTick& tick : recording.ticks) {
      writer.begin_tick(tick.tick);
      for (const RecordedInput& input : tick.inputs) writer.add_input(input);
      writer.end_tick();
    }
    EXPECT_TRUE(writer.full());
    EXPECT_NE(writer.stopped_reason().find(with_number("limit of ", max) + " bytes"),
              std::string::npos)
        << writer.stopped_reason();
    const auto bytes = writer.finish();
    EXPECT_LE(bytes.size(), max);
    const Recording back = read_ok(bytes);
    EXPECT_TRUE(back.complete);
    EXPECT_TRUE(back.truncated);
    EXPECT_LT(back.ticks.size(), recording.ticks.size());
    for (std::size_t i = 0; i < back.ticks.size(); ++i) {
      EXPECT_EQ(back.ticks[i].tick, recording.ticks[i].tick);
      ASSERT_EQ(back.ticks[i].inputs.size(), recording.ticks[i].inputs.size());
    }
  }
}

TEST(RecordingTest, WriterStopsOnCallsOutOfOrder) {
  RecordingWriter writer(sample_header(), 1 << 20);
  writer.begin_tick(5);
  writer.end_tick();
  writer.begin_tick(5);
  EXPECT_TRUE(writer.full());
  EXPECT_EQ(writer.stopped_reason(), "tick 5 began after tick 5");
  EXPECT_EQ(read_ok(writer.finish()).ticks.size(), 1u);

  RecordingWriter outside(sample_header(), 1 << 20);
  outside.add_input({});
  EXPECT_EQ(outside.stopped_reason(), "an input outside begin_tick/end_tick");

  RecordingWriter twice(sample_header(), 1 << 20);
  twice.begin_tick(1);
  RecordedInput input;
  input.entity_id = 3;
  twice.add_input(input);
  twice.add_input(input);
  EXPECT_EQ(twice.stopped_reason(), "a second input of entity 3 in tick 1");

  RecordingWriter bad(sample_header(), 1 << 20);
  bad.begin_tick(1);
  input.input.yaw_rad = NAN;
  bad.add_input(input);
  EXPECT_EQ(bad.stopped_reason(), "entity 3 in tick 1: a move or view component is not finite");

  RecordingWriter name(sample_header(), 1 << 20);
  name.begin_tick(1);
  name.add_event({RecordedEventKind::Connect, 1, std::string(33, 'x'), 0});
  EXPECT_EQ(name.stopped_reason(), "a connect's name must be 1..32 bytes, got 33");
}

/// A file with the sample header and the given tick chunk payloads (and a matching footer when
/// `footer` is set), framed and checksummed as the writer does.
std::vector<std::uint8_t> craft(const std::vector<std::vector<std::uint8_t>>& chunks,
                                std::vector<std::uint8_t> footer = {}) {
  RecordingWriter writer(sample_header(), 1 << 20);
  auto bytes = writer.finish();
  bytes.resize(chunk_starts(bytes)[1]);  // magic, version, header
  for (const auto& chunk : chunks) rf::put_chunk(bytes, rf::kChunkTicks, chunk);
  if (!footer.empty()) {
    rf::put_u32(footer, rf::crc32(bytes));
    rf::put_chunk(bytes, rf::kChunkFooter, footer);
  }
  return bytes;
}

std::string read_error(const std::vector<std::uint8_t>& bytes) {
  const auto result = read_recording(bytes);
  const auto* error = std::get_if<RecordingError>(&result);
  return error ? error->message : "(read fine)";
}

TEST(RecordingTest, ReaderRefusesBadValuesWithCorrectChecksums) {
  const auto tick = [](std::uint64_t delta, std::uint8_t flags) {
    std::vector<std::uint8_t> out;
    rf::put_varint(out, delta << rf::kTickFlagBits | flags);
    return out;
  };
  auto zero_delta = tick(0, 0);
  EXPECT_EQ(read_error(craft({zero_delta})),
            "chunk 1 (ticks): tick delta must be 1..4294967295 after tick 0, got 0");

  auto many = tick(1, rf::kTickEntities);
  rf::put_varint(many, 65);
  EXPECT_EQ(read_error(craft({many})),
            "chunk 1 (ticks), tick 1: entity count must be at most 64, got 65");

  auto twice = tick(1, rf::kTickEntities);
  rf::put_varint(twice, 2);
  rf::put_varint(twice, 9);
  rf::put_varint(twice, 9);
  EXPECT_EQ(read_error(craft({twice})), "chunk 1 (ticks), tick 1: entity 9 listed twice");

  auto kind = tick(1, rf::kTickEvents);
  rf::put_varint(kind, 1);
  kind.push_back(9);
  EXPECT_EQ(read_error(craft({kind})), "chunk 1 (ticks), tick 1: event kind must be 1..5, got 9");

  auto reason = tick(1, rf::kTickEvents);
  rf::put_varint(reason, 1);
  reason.push_back(static_cast<std::uint8_t>(RecordedEventKind::End));
  rf::put_varint(reason, 7);
  EXPECT_EQ(read_error(craft({reason})),
            "chunk 1 (ticks), tick 1: end reason must be a MatchEndReason, got 7");

  auto nan = tick(3, rf::kTickEntities | rf::kTickChanges);
  rf::put_varint(nan, 1);
  rf::put_varint(nan, 4);
  rf::put_varint(nan, rf::kFieldYaw);
  rf::put_u32(nan, 0x7FC00000u);
  EXPECT_EQ(read_error(craft({nan})),
            "chunk 1 (ticks), tick 3: entity 4: a move or view component is not finite");

  auto mask = tick(1, rf::kTickEntities | rf::kTickChanges);
  rf::put_varint(mask, 1);
  rf::put_varint(mask, 4);
  rf::put_varint(mask, 1u << 12);
  EXPECT_EQ(read_error(craft({mask})),
            "chunk 1 (ticks), tick 1: change mask has unknown bits 4096");

  auto cut = tick(1, rf::kTickHash);
  cut.push_back(1);
  EXPECT_EQ(read_error(craft({cut})),
            "chunk 1 (ticks), tick 1: state hash runs past the end of the chunk (expected 8 "
            "bytes, 1 left)");

  std::vector<std::uint8_t> footer;
  for (int i = 0; i < 6; ++i) rf::put_varint(footer, i == 0 ? 2 : (i == 4 ? 1 : (i == 5 ? 1 : 0)));
  footer.push_back(0);
  EXPECT_EQ(read_error(craft({tick(1, 0)}, footer)),
            "chunk 2 (footer): the footer says 2 ticks, the chunks hold 1");

  auto extra = write(random_recording(1, 10));
  extra.push_back(0);
  EXPECT_EQ(read_error(extra), "1 bytes after the footer");

  auto magic = write(random_recording(1, 10));
  magic[0] = 'X';
  EXPECT_EQ(read_error(magic),
            "not a ricochet recording (the file does not start with \"RCREC\\r\\n\\x1a\")");
  magic[0] = 'R';
  magic[8] = 3;
  EXPECT_EQ(read_error(magic), "recording format version 3, this build reads versions 1 to 2");
  magic[8] = 0;
  EXPECT_EQ(read_error(magic), "recording format version 0, this build reads versions 1 to 2");
  EXPECT_EQ(read_error({}), "truncated at byte 0 in the magic (expected 9 more bytes)");
}

TEST(RecordingTest, AFooterWhosePlayerCountDisagreesWithTheConnectsIsRefused) {
  // One tick with a Connect of account 7 (and a second one of it), then a footer counting
  // `players`, checksums right.
  std::vector<std::uint8_t> tick;
  rf::put_varint(tick, 1u << rf::kTickFlagBits | rf::kTickEvents);
  rf::put_varint(tick, 2);
  for (int i = 0; i < 2; ++i) {
    tick.push_back(static_cast<std::uint8_t>(RecordedEventKind::Connect));
    rf::put_varint(tick, 7);
    rf::put_string(tick, "ann");
  }
  const auto file = [&](std::uint64_t players) {
    std::vector<std::uint8_t> footer;
    const std::uint64_t totals[] = {1, 2, 0, 0, 1, 1};  // ticks .. tick chunks
    for (const std::uint64_t total : totals) rf::put_varint(footer, total);
    footer.push_back(0);
    rf::put_varint(footer, players);
    return craft({tick}, footer);
  };
  const auto tail = [](const std::vector<std::uint8_t>& bytes) {
    return read_recording_footer(std::span(bytes).last(kMaxRecordingFooterBytes));
  };
  EXPECT_EQ(read_ok(file(1)).players, 1u) << "the same account twice is one player";
  ASSERT_TRUE(tail(file(1)).has_value());
  EXPECT_EQ(tail(file(1))->players, 1u);
  EXPECT_EQ(read_error(file(2)),
            "chunk 2 (footer): the footer says 2 players (distinct accounts with a Connect "
            "event), the chunks hold 1");
  ASSERT_TRUE(tail(file(2)).has_value()) << "no more than the events: the listing cannot tell";
  EXPECT_EQ(tail(file(2))->players, 2u);
  EXPECT_EQ(read_error(file(0)),
            "chunk 2 (footer): the footer says 0 players (distinct accounts with a Connect "
            "event), the chunks hold 1");
  EXPECT_EQ(read_error(file(3)),
            "chunk 2 (footer): the footer says 3 players (distinct accounts with a Connect "
            "event), the chunks hold 1");
  EXPECT_FALSE(tail(file(3)).has_value()) << "more players than events";
  EXPECT_EQ(read_error(file(std::uint64_t{1} << 32)),
            "chunk 2 (footer): player count must be at most 4294967295, got 4294967296");
  EXPECT_FALSE(tail(file(std::uint64_t{1} << 32)).has_value());
}

/// A scripted 60 Hz stream as a real player sends it: the mouse turns every tick and pitches
/// most ticks, movement keys change a few times a second, fire in bursts, the view tick follows
/// the tick, the interpolation fraction wobbles, the latency estimate moves twice a second, and
/// a hash every 60 ticks.
TEST(RecordingTest, BytesPerPlayerMinuteOfAScripted60HzStream) {
  constexpr int kPlayers = 8;
  constexpr std::uint32_t kTicks = 60 * 60;
  RecordingHeader header = sample_header();
  header.map_files.clear();
  header.hash_interval_ticks = 60;
  RecordingWriter writer(header, 64u << 20);
  const std::size_t empty = writer.bytes();
  std::mt19937 rng(5);
  std::vector<RecordedInput> players(kPlayers);
  for (std::uint32_t tick = 1; tick <= kTicks; ++tick) {
    writer.begin_tick(tick);
    if (tick == 1) {
      for (int p = 0; p < kPlayers; ++p) {
        writer.add_event({RecordedEventKind::Connect, 100u + p,
                          with_number("p", static_cast<std::uint64_t>(p)), 0});
      }
    }
    for (int p = 0; p < kPlayers; ++p) {
      RecordedInput& player = players[static_cast<std::size_t>(p)];
      PlayerInput& in = player.input;
      player.entity_id = static_cast<std::uint32_t>(p + 1);
      in.sequence = tick;
      in.yaw_rad = std::remainder(in.yaw_rad + 0.01f * std::sin(tick * 0.05f + p), 6.2831853f);
      if (tick % 4 != 0) in.pitch_rad = 0.3f * std::sin(tick * 0.02f + p);
      if ((tick + 7 * p) % 20 == 0) {
        in.move_right = static_cast<float>(static_cast<int>(rng() % 3) - 1);
        in.move_forward = in.move_right == 0 ? 1.0f : 0.0f;
      }
      const bool firing = (tick / 90 + p) % 3 == 0;
      in.buttons = firing ? std::uint32_t{proto::kButtonFire} : 0u;
      if ((tick + 13 * p) % 600 == 0) in.weapon_slot = 1 + rng() % 3;
      in.view_tick = tick > 3 ? tick - 3 : 0;
      in.view_fraction = static_cast<std::uint8_t>(128 + rng() % 16);
      if (tick % 30 == 0) player.latency_us = 20'000 + rng() % 2'000;
      writer.add_input(player);
    }
    writer.end_tick();
    if (tick % 60 == 0) writer.add_hash(tick, (std::uint64_t{rng()} << 32) | rng());
  }
  const auto bytes = writer.finish();
  ASSERT_TRUE(writer.stopped_reason().empty()) << writer.stopped_reason();
  const double per_player_minute = static_cast<double>(bytes.size() - empty) / kPlayers;
  std::printf(
      "recording: %zu bytes for %d players x 1 min at 60 Hz: %.0f bytes per player-minute\n",
      bytes.size(), kPlayers, per_player_minute);
  EXPECT_LT(per_player_minute, 40'000) << "about 11 bytes per player tick";
  EXPECT_EQ(read_ok(bytes).ticks.size(), kTicks);
}

TEST(RecordingTest, ARecordingOfManyBlocksRoundTripsAndItsSizeIsCountedAsItGrows) {
  // The writer keeps the file in blocks of 256 KiB that never move; this one spans several.
  const Recording recording = random_recording(7, 4000);
  RecordingWriter writer(recording.header, 64u << 20);
  std::size_t next_hash = 0;
  std::size_t last_bytes = writer.bytes();
  for (const RecordedTick& tick : recording.ticks) {
    write_tick(writer, recording, tick, next_hash);
    ASSERT_GE(writer.bytes(), last_bytes);
    last_bytes = writer.bytes();
  }
  const std::size_t counted = writer.bytes();
  const auto bytes = writer.finish();
  ASSERT_GT(bytes.size(), std::size_t{3} << 18) << "spans more than three blocks";
  EXPECT_GE(bytes.size(), counted);
  const Recording back = read_ok(bytes);
  EXPECT_TRUE(back.complete);
  EXPECT_FALSE(back.truncated);
  EXPECT_EQ(back.ticks.size(), recording.ticks.size());
  EXPECT_EQ(back.hashes.size(), recording.hashes.size());
  expect_prefix(recording, back);
}

}  // namespace
}  // namespace ricochet::server::recording_test
