/// read_recording() (recording.h): checks every frame, length, count and value before use.

#include <algorithm>
#include <bit>
#include <limits>
#include <utility>

#include "recording_format.h"
#include "ricochet/proto/weapon_wire.h"
#include "ricochet/server/recording.h"

namespace ricochet::server {

namespace rf = recording_format;

namespace {

/// Thrown inside this file only; read_recording() turns it into a RecordingError.
struct Failure {
  std::string message;
  std::uint64_t offset;
};

std::string hex32(std::uint32_t value) {
  static const char* const kDigits = "0123456789abcdef";
  std::string text = "0x";
  for (int shift = 28; shift >= 0; shift -= 4) text += kDigits[(value >> shift) & 0xF];
  return text;
}

/// Reads one chunk's payload; positions are file offsets for the messages.
class Cursor {
 public:
  Cursor(std::span<const std::uint8_t> bytes, std::uint64_t base, std::string where)
      : bytes_(bytes), base_(base), where_(std::move(where)) {}

  bool at_end() const { return pos_ == bytes_.size(); }
  std::uint64_t offset() const { return base_ + pos_; }
  void set_tick(std::uint32_t tick) { tick_ = tick; }

  [[noreturn]] void fail(const std::string& what) const {
    std::string message = where_;
    if (tick_ != 0) message += ", tick " + std::to_string(tick_);
    message += ": ";
    message += what;
    throw Failure{std::move(message), offset()};
  }

  std::uint8_t u8(const char* what) {
    need(1, what);
    return bytes_[pos_++];
  }
  std::uint32_t u32(const char* what) {
    need(4, what);
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) value |= std::uint32_t{bytes_[pos_++]} << (8 * i);
    return value;
  }
  std::uint64_t u64(const char* what) {
    need(8, what);
    std::uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= std::uint64_t{bytes_[pos_++]} << (8 * i);
    return value;
  }
  float f32(const char* what) { return std::bit_cast<float>(u32(what)); }

  std::uint64_t varint(const char* what) {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const std::uint8_t byte = u8(what);
      if (shift == 63 && byte > 1) break;
      value |= std::uint64_t{byte & 0x7Fu} << shift;
      if ((byte & 0x80) == 0) return value;
    }
    std::string message = what;
    message += ": a varint longer than 64 bits";
    fail(message);
  }
  /// A varint that must be at most `max`.
  std::uint64_t bounded(const char* what, std::uint64_t max) {
    const std::uint64_t value = varint(what);
    if (value > max) {
      std::string message = what;
      message += " must be at most " + std::to_string(max) + ", got " + std::to_string(value);
      fail(message);
    }
    return value;
  }
  std::string string(const char* what, std::size_t max) {
    const std::size_t size = bounded(what, max);
    need(size, what);
    std::string text(reinterpret_cast<const char*>(bytes_.data() + pos_), size);
    pos_ += size;
    return text;
  }
  std::span<const std::uint8_t> take(std::size_t size, const char* what) {
    need(size, what);
    const auto span = bytes_.subspan(pos_, size);
    pos_ += size;
    return span;
  }

 private:
  void need(std::size_t size, const char* what) const {
    if (bytes_.size() - pos_ >= size) return;
    std::string message = what;
    message += " runs past the end of the chunk (expected " + std::to_string(size) + " bytes, " +
               std::to_string(bytes_.size() - pos_) + " left)";
    fail(message);
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  std::uint64_t base_;
  std::string where_;
  std::uint32_t tick_ = 0;
};

/// A u32 that is `expected + delta` for a zigzag-coded delta; fails when out of range.
std::uint32_t add_delta(Cursor& in, std::uint32_t expected, const char* what) {
  const std::int64_t delta = rf::unzigzag(in.varint(what));
  const std::int64_t value = static_cast<std::int64_t>(expected) + delta;
  if (delta < -(std::int64_t{1} << 33) || delta > (std::int64_t{1} << 33) || value < 0 ||
      value > std::numeric_limits<std::uint32_t>::max()) {
    std::string message = what;
    message += " out of the 32-bit range";
    in.fail(message);
  }
  return static_cast<std::uint32_t>(value);
}

RecordingHeader read_header(Cursor& in) {
  RecordingHeader header;
  header.server_version = in.string("server_version", kMaxRecordedVersionBytes);
  const std::size_t files = in.bounded("map file count", kMaxRecordedMapFiles);
  for (std::size_t i = 0; i < files; ++i) {
    RecordedFile file;
    file.path = in.string("map file path", kMaxRecordedPathBytes);
    file.text = in.string("map file text", kMaxRecordedMapFileBytes);
    header.map_files.push_back(std::move(file));
  }
  const std::size_t config = in.bounded("config size", kMaxRecordedConfigBytes);
  const auto config_bytes = in.take(config, "config");
  header.config.assign(config_bytes.begin(), config_bytes.end());
  header.seed = in.u64("seed");
  header.hash_interval_ticks =
      static_cast<std::uint32_t>(in.bounded("hash_interval_ticks", rf::kMaxHashInterval));
  header.tick_rate_hz = static_cast<std::uint32_t>(in.bounded("tick_rate_hz", rf::kMaxTickRate));
  if (std::string error = rf::check_header(header); !error.empty()) in.fail(error);
  if (!in.at_end()) in.fail("bytes after the header's last field");
  return header;
}

/// Decoder state carried from tick record to tick record, across chunks.
struct TickState {
  std::uint32_t last_tick = 0;
  std::vector<std::uint32_t> entities;
  std::vector<RecordedInput> previous;  ///< by entity id

  RecordedInput& previous_of(std::uint32_t id) {
    const auto it = std::lower_bound(
        previous.begin(), previous.end(), id,
        [](const RecordedInput& input, std::uint32_t key) { return input.entity_id < key; });
    if (it != previous.end() && it->entity_id == id) return *it;
    RecordedInput fresh;
    fresh.entity_id = id;
    return *previous.insert(it, fresh);
  }
};

RecordedEvent read_event(Cursor& in) {
  RecordedEvent event;
  const std::uint8_t kind = in.u8("event kind");
  event.kind = static_cast<RecordedEventKind>(kind);
  if (kind < static_cast<std::uint8_t>(RecordedEventKind::Connect) ||
      kind > static_cast<std::uint8_t>(RecordedEventKind::End)) {
    in.fail(rf::check_event(event));
  }
  if (event.kind == RecordedEventKind::End) {
    event.end_reason = static_cast<std::uint32_t>(
        in.bounded("end reason", std::numeric_limits<std::uint32_t>::max()));
  } else {
    event.account = in.varint("account");
    if (event.kind == RecordedEventKind::Connect) {
      event.name = in.string("name", kMaxRecordedNameBytes);
    }
  }
  if (std::string error = rf::check_event(event); !error.empty()) in.fail(error);
  return event;
}

RecordedInput read_input(Cursor& in, const RecordedInput& before) {
  const std::uint64_t mask = in.varint("change mask");
  if ((mask & ~std::uint64_t{rf::kKnownFields}) != 0) {
    in.fail("change mask has unknown bits " +
            std::to_string(mask & ~std::uint64_t{rf::kKnownFields}));
  }
  RecordedInput now = before;
  PlayerInput& b = now.input;
  const PlayerInput& a = before.input;
  if (mask & rf::kFieldYaw) b.yaw_rad = in.f32("yaw");
  if (mask & rf::kFieldPitch) b.pitch_rad = in.f32("pitch");
  if (mask & rf::kFieldMoveRight) b.move_right = in.f32("move_right");
  if (mask & rf::kFieldMoveForward) b.move_forward = in.f32("move_forward");
  if (mask & rf::kFieldButtons) {
    b.buttons = static_cast<std::uint32_t>(
        in.bounded("buttons", std::numeric_limits<std::uint32_t>::max()));
  }
  if (mask & rf::kFieldViewFraction) b.view_fraction = in.u8("view_fraction");
  b.sequence = a.sequence + 1;
  if (mask & rf::kFieldSequence) b.sequence = add_delta(in, a.sequence + 1, "sequence");
  b.view_tick = rf::expected_view_tick(a.view_tick);
  if (mask & rf::kFieldViewTick) b.view_tick = add_delta(in, b.view_tick, "view_tick");
  if (mask & rf::kFieldWeaponSlot) {
    b.weapon_slot = static_cast<std::uint32_t>(in.bounded("weapon_slot", proto::kMaxWeaponSlot));
  }
  if (mask & rf::kFieldLatency) now.latency_us = add_delta(in, before.latency_us, "latency_us");
  if (std::string error = rf::check_input(b); !error.empty()) {
    in.fail("entity " + std::to_string(now.entity_id) + ": " + error);
  }
  return now;
}

void read_ticks(Cursor& in, TickState& state, Recording& recording) {
  while (!in.at_end()) {
    const std::uint64_t head = in.varint("tick record");
    const std::uint64_t delta = head >> rf::kTickFlagBits;
    const std::uint64_t flags = head & ((1u << rf::kTickFlagBits) - 1);
    if (delta == 0 || delta > std::numeric_limits<std::uint32_t>::max() - state.last_tick) {
      in.fail("tick delta must be 1.." +
              std::to_string(std::numeric_limits<std::uint32_t>::max() - state.last_tick) +
              " after tick " + std::to_string(state.last_tick) + ", got " + std::to_string(delta));
    }
    RecordedTick tick;
    tick.tick = state.last_tick + static_cast<std::uint32_t>(delta);
    in.set_tick(tick.tick);
    if (flags & rf::kTickEvents) {
      const std::size_t count = in.bounded("event count", kMaxRecordedEventsPerTick);
      for (std::size_t i = 0; i < count; ++i) tick.events.push_back(read_event(in));
    }
    if (flags & rf::kTickEntities) {
      const std::size_t count = in.bounded("entity count", kMaxRecordedPlayers);
      state.entities.clear();
      for (std::size_t i = 0; i < count; ++i) {
        const auto id = static_cast<std::uint32_t>(
            in.bounded("entity id", std::numeric_limits<std::uint32_t>::max()));
        if (std::find(state.entities.begin(), state.entities.end(), id) != state.entities.end()) {
          in.fail("entity " + std::to_string(id) + " listed twice");
        }
        state.entities.push_back(id);
      }
    }
    for (const std::uint32_t id : state.entities) {
      RecordedInput& before = state.previous_of(id);
      if (flags & rf::kTickChanges)
        before = read_input(in, before);
      else {
        before.input.sequence += 1;
        before.input.view_tick = rf::expected_view_tick(before.input.view_tick);
      }
      tick.inputs.push_back(before);
    }
    if (flags & rf::kTickHash) recording.hashes.push_back({tick.tick, in.u64("state hash")});
    state.last_tick = tick.tick;
    recording.ticks.push_back(std::move(tick));
  }
  in.set_tick(0);
}

struct Totals {
  std::uint64_t ticks = 0, events = 0, inputs = 0, hashes = 0, chunks = 0;
  std::uint32_t last_tick = 0;
};

/// Distinct accounts with a Connect event in `ticks`.
std::uint64_t connected_accounts(const std::vector<RecordedTick>& ticks) {
  std::vector<std::uint64_t> accounts;
  for (const RecordedTick& tick : ticks) {
    for (const RecordedEvent& event : tick.events) {
      if (event.kind == RecordedEventKind::Connect) accounts.push_back(event.account);
    }
  }
  std::sort(accounts.begin(), accounts.end());
  return static_cast<std::uint64_t>(std::unique(accounts.begin(), accounts.end()) -
                                    accounts.begin());
}

/// Compares the footer of a file of `version` with what the chunks held, sets the recording's
/// truncated flag and player count.
void read_footer(Cursor& in, std::uint8_t version, const Totals& totals, std::uint32_t file_crc,
                 Recording& recording) {
  const auto expect = [&](const char* what, std::uint64_t stored, std::uint64_t counted) {
    if (stored == counted) return;
    std::string message = "the footer says ";
    message += std::to_string(stored) + " " + what + ", the chunks hold " + std::to_string(counted);
    in.fail(message);
  };
  expect("ticks", in.varint("tick count"), totals.ticks);
  expect("events", in.varint("event count"), totals.events);
  expect("inputs", in.varint("input count"), totals.inputs);
  expect("hashes", in.varint("hash count"), totals.hashes);
  expect("as the last tick", in.varint("last tick"), totals.last_tick);
  expect("tick chunks", in.varint("tick chunk count"), totals.chunks);
  const std::uint8_t truncated = in.u8("truncated flag");
  if (truncated > 1) in.fail("truncated flag must be 0 or 1, got " + std::to_string(truncated));
  recording.truncated = truncated == 1;
  if (version >= 2) {
    const auto players = static_cast<std::uint32_t>(
        in.bounded("player count", std::numeric_limits<std::uint32_t>::max()));
    expect("players (distinct accounts with a Connect event)", players,
           connected_accounts(recording.ticks));
    recording.players = players;
  }
  const std::uint32_t stored = in.u32("file checksum");
  if (stored != file_crc) {
    in.fail("file CRC-32 mismatch (stored " + hex32(stored) + ", computed " + hex32(file_crc) +
            ")");
  }
  if (!in.at_end()) in.fail("bytes after the footer's last field");
}

std::uint32_t read_le32(std::span<const std::uint8_t> bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= std::uint32_t{bytes[at + i]} << (8 * i);
  return value;
}

Recording read_all(std::span<const std::uint8_t> bytes) {
  if (bytes.size() > kMaxRecordingBytes) {
    throw Failure{"a recording is at most " + std::to_string(kMaxRecordingBytes) + " bytes, got " +
                      std::to_string(bytes.size()),
                  0};
  }
  const std::size_t prefix = rf::kMagic.size() + 1;
  if (bytes.size() < prefix) {
    throw Failure{"truncated at byte " + std::to_string(bytes.size()) + " in the magic (expected " +
                      std::to_string(prefix - bytes.size()) + " more bytes)",
                  bytes.size()};
  }
  if (!std::equal(rf::kMagic.begin(), rf::kMagic.end(), bytes.begin())) {
    throw Failure{"not a ricochet recording (the file does not start with \"RCREC\\r\\n\\x1a\")",
                  0};
  }
  const std::uint8_t version = bytes[rf::kMagic.size()];
  if (version < rf::kOldestVersion || version > rf::kVersion) {
    throw Failure{"recording format version " + std::to_string(version) +
                      ", this build reads versions " + std::to_string(rf::kOldestVersion) + " to " +
                      std::to_string(rf::kVersion),
                  rf::kMagic.size()};
  }
  Recording recording;
  TickState state;
  Totals totals;
  std::size_t pos = prefix;
  bool have_header = false;
  for (std::uint64_t index = 0;; ++index) {
    std::string where = "chunk " + std::to_string(index);
    const auto truncated = [&](std::size_t missing) -> Failure {
      return {"truncated at byte " + std::to_string(bytes.size()) + " in " + where + " (expected " +
                  std::to_string(missing) + " more bytes)",
              bytes.size()};
    };
    // A cut after the header: everything before the chunk it falls in stands.
    const auto cut = [&](std::string what) {
      recording.cut = std::move(what) + "; replayable to tick " + std::to_string(state.last_tick);
      recording.cut_offset = pos;
    };
    if (pos == bytes.size() && have_header) {
      cut("ends after chunk " + std::to_string(index - 1) + " at byte " + std::to_string(pos) +
          " with no footer");
      return recording;
    }
    if (bytes.size() - pos < rf::kFrameHeadBytes) {
      if (!have_header) throw truncated(rf::kFrameHeadBytes - (bytes.size() - pos));
      cut("cut inside " + where + " at byte " + std::to_string(pos) + " (" +
          std::to_string(bytes.size() - pos) + " of its " + std::to_string(rf::kFrameHeadBytes) +
          " frame bytes there)");
      return recording;
    }
    const std::uint8_t type = bytes[pos];
    const std::uint32_t length = read_le32(bytes, pos + 1);
    const std::uint32_t head_crc = read_le32(bytes, pos + 5);
    const std::uint32_t head_computed = rf::crc32(bytes.subspan(pos, 5));
    if (head_crc != head_computed) {
      throw Failure{where + " at byte " + std::to_string(pos) + ": frame CRC-32 mismatch (stored " +
                        hex32(head_crc) + ", computed " + hex32(head_computed) + ")",
                    pos};
    }
    where += " (";
    where += rf::chunk_name(type);
    where += ")";
    const bool known =
        type == rf::kChunkHeader || type == rf::kChunkTicks || type == rf::kChunkFooter;
    std::string order_error;
    if (!known)
      order_error = "unknown chunk type " + std::to_string(type);
    else if (!have_header && type != rf::kChunkHeader)
      order_error = "the first chunk must be the header";
    else if (have_header && type == rf::kChunkHeader)
      order_error = "a second header";
    if (!order_error.empty())
      throw Failure{where + " at byte " + std::to_string(pos) + ": " + order_error, pos};
    const std::size_t max_length = type == rf::kChunkTicks    ? rf::kMaxTickChunkBytes
                                   : type == rf::kChunkFooter ? rf::kMaxFooterBytes
                                                              : kMaxRecordingBytes;
    if (length > max_length) {
      throw Failure{where + " at byte " + std::to_string(pos) + ": length " +
                        std::to_string(length) + " over the limit of " + std::to_string(max_length),
                    pos};
    }
    const std::size_t payload_at = pos + rf::kFrameHeadBytes;
    const std::size_t available = bytes.size() - payload_at;
    if (available < std::size_t{length} + 4) {
      if (!have_header) throw truncated(length + 4 - available);
      cut("cut inside " + where + " at byte " + std::to_string(pos) + " (" +
          std::to_string(bytes.size() - pos) + " of its " +
          std::to_string(rf::kFrameBytes + length) + " bytes there)");
      return recording;
    }
    const auto payload = bytes.subspan(payload_at, length);
    const std::uint32_t stored = read_le32(bytes, payload_at + length);
    const std::uint32_t computed = rf::crc32(payload);
    if (stored != computed) {
      throw Failure{where + " at byte " + std::to_string(pos) + ": CRC-32 mismatch (stored " +
                        hex32(stored) + ", computed " + hex32(computed) + ")",
                    pos};
    }
    Cursor in(payload, payload_at, where);
    if (type == rf::kChunkHeader) {
      recording.header = read_header(in);
      have_header = true;
    } else if (type == rf::kChunkTicks) {
      const std::size_t ticks_before = recording.ticks.size();
      const std::size_t hashes_before = recording.hashes.size();
      read_ticks(in, state, recording);
      ++totals.chunks;
      totals.ticks += recording.ticks.size() - ticks_before;
      totals.hashes += recording.hashes.size() - hashes_before;
      for (std::size_t i = ticks_before; i < recording.ticks.size(); ++i) {
        totals.events += recording.ticks[i].events.size();
        totals.inputs += recording.ticks[i].inputs.size();
      }
      totals.last_tick = state.last_tick;
    } else {
      read_footer(in, version, totals, rf::crc32(bytes.first(pos)), recording);
      recording.complete = true;
      const std::size_t end = payload_at + length + 4;
      if (end != bytes.size()) {
        throw Failure{std::to_string(bytes.size() - end) + " bytes after the footer", end};
      }
      return recording;
    }
    pos = payload_at + length + 4;
  }
}

}  // namespace

std::variant<Recording, RecordingError> read_recording(std::span<const std::uint8_t> bytes) {
  try {
    return read_all(bytes);
  } catch (const Failure& failure) {
    return RecordingError{failure.message, failure.offset};
  }
}

std::variant<std::size_t, RecordingError> recording_header_bytes(
    std::span<const std::uint8_t> first) {
  const std::size_t prefix = rf::kMagic.size() + 1;
  if (first.size() < prefix + 5) {
    // read_all names what is wrong with so few bytes: a short magic, or a cut in the header.
    auto read = read_recording(first);
    if (auto* bad = std::get_if<RecordingError>(&read)) return std::move(*bad);
    return RecordingError{"no header chunk", first.size()};
  }
  if (!std::equal(rf::kMagic.begin(), rf::kMagic.end(), first.begin()) ||
      first[rf::kMagic.size()] < rf::kOldestVersion || first[rf::kMagic.size()] > rf::kVersion) {
    return std::get<RecordingError>(read_recording(first.first(prefix)));
  }
  if (first[prefix] != rf::kChunkHeader) {
    return RecordingError{
        "chunk 0 at byte " + std::to_string(prefix) + ": the first chunk must be the header",
        prefix};
  }
  const std::uint64_t total =
      prefix + rf::kFrameBytes + std::uint64_t{read_le32(first, prefix + 1)};
  if (total > kMaxRecordingHeaderBytes) {
    return RecordingError{"chunk 0 (header) at byte " + std::to_string(prefix) + ": " +
                              std::to_string(total) + " bytes, over the listing's limit of " +
                              std::to_string(kMaxRecordingHeaderBytes),
                          prefix};
  }
  return static_cast<std::size_t>(total);
}

std::variant<RecordingHeader, RecordingError> read_recording_header(
    std::span<const std::uint8_t> head) {
  auto size = recording_header_bytes(head.first(std::min<std::size_t>(head.size(), 14)));
  if (auto* bad = std::get_if<RecordingError>(&size)) return std::move(*bad);
  auto read = read_recording(head.first(std::min(head.size(), std::get<std::size_t>(size))));
  if (auto* bad = std::get_if<RecordingError>(&read)) return std::move(*bad);
  return std::move(std::get<Recording>(read).header);
}

std::optional<RecordingFooter> read_recording_footer(std::span<const std::uint8_t> tail) {
  // The footer chunk ends the file: try each place its frame could start, nearest the end last.
  for (std::size_t start =
           tail.size() > kMaxRecordingFooterBytes ? tail.size() - kMaxRecordingFooterBytes : 0;
       start + rf::kFrameBytes <= tail.size(); ++start) {
    if (tail[start] != rf::kChunkFooter) continue;
    const std::uint32_t length = read_le32(tail, start + 1);
    if (start + rf::kFrameBytes + std::size_t{length} != tail.size()) continue;
    if (read_le32(tail, start + 5) != rf::crc32(tail.subspan(start, 5))) continue;
    const auto payload = tail.subspan(start + rf::kFrameHeadBytes, length);
    if (read_le32(tail, start + rf::kFrameHeadBytes + length) != rf::crc32(payload)) continue;
    try {
      Cursor in(payload, 0, "footer");
      RecordingFooter footer;
      footer.ticks = in.varint("tick count");
      footer.events = in.varint("event count");
      footer.inputs = in.varint("input count");
      footer.hashes = in.varint("hash count");
      footer.last_tick = static_cast<std::uint32_t>(
          in.bounded("last tick", std::numeric_limits<std::uint32_t>::max()));
      footer.tick_chunks = in.varint("tick chunk count");
      const std::uint8_t truncated = in.u8("truncated flag");
      // Version 1 ends with the file checksum here; version 2 has the player count before it.
      if (payload.size() > in.offset() + 4) {
        const std::uint64_t players =
            in.bounded("player count", std::numeric_limits<std::uint32_t>::max());
        if (players > footer.events) continue;  // each came with a Connect event
        footer.players = static_cast<std::uint32_t>(players);
      }
      in.u32("file checksum");
      if (truncated > 1 || !in.at_end()) continue;
      footer.truncated = truncated == 1;
      return footer;
    } catch (const Failure&) {
      continue;
    }
  }
  return std::nullopt;
}

}  // namespace ricochet::server
