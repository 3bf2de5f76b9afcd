/// RecordingWriter (recording.h): encodes ticks into chunks in memory, within max_bytes.

#include <algorithm>
#include <bit>
#include <utility>

#include "recording_format.h"
#include "ricochet/server/recording.h"

namespace ricochet::server {

namespace rf = recording_format;

namespace {

/// Room kept for the last chunk's framing and the footer, so finish() stays within max_bytes.
constexpr std::size_t kFinishReserve = 2 * rf::kFrameBytes + rf::kMaxFooterBytes;
/// The file grows in blocks of this many bytes (about 16 tick chunks).
constexpr std::size_t kBlockBytes = 256 * 1024;

bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

void put_float(std::vector<std::uint8_t>& out, float value) {
  rf::put_u32(out, std::bit_cast<std::uint32_t>(value));
}

/// Appends the change mask of `now` against `before` and the changed fields.
void put_input_change(std::vector<std::uint8_t>& out, const RecordedInput& before,
                      const RecordedInput& now) {
  const PlayerInput& a = before.input;
  const PlayerInput& b = now.input;
  std::uint32_t mask = 0;
  if (!same_bits(a.yaw_rad, b.yaw_rad)) mask |= rf::kFieldYaw;
  if (!same_bits(a.pitch_rad, b.pitch_rad)) mask |= rf::kFieldPitch;
  if (!same_bits(a.move_right, b.move_right)) mask |= rf::kFieldMoveRight;
  if (!same_bits(a.move_forward, b.move_forward)) mask |= rf::kFieldMoveForward;
  if (a.buttons != b.buttons) mask |= rf::kFieldButtons;
  if (a.view_fraction != b.view_fraction) mask |= rf::kFieldViewFraction;
  if (b.sequence != a.sequence + 1) mask |= rf::kFieldSequence;
  if (b.view_tick != rf::expected_view_tick(a.view_tick)) mask |= rf::kFieldViewTick;
  if (a.weapon_slot != b.weapon_slot) mask |= rf::kFieldWeaponSlot;
  if (before.latency_us != now.latency_us) mask |= rf::kFieldLatency;
  rf::put_varint(out, mask);
  if (mask & rf::kFieldYaw) put_float(out, b.yaw_rad);
  if (mask & rf::kFieldPitch) put_float(out, b.pitch_rad);
  if (mask & rf::kFieldMoveRight) put_float(out, b.move_right);
  if (mask & rf::kFieldMoveForward) put_float(out, b.move_forward);
  if (mask & rf::kFieldButtons) rf::put_varint(out, b.buttons);
  if (mask & rf::kFieldViewFraction) out.push_back(b.view_fraction);
  const auto delta = [](std::uint32_t value, std::uint32_t expected) {
    return rf::zigzag(static_cast<std::int64_t>(value) - static_cast<std::int64_t>(expected));
  };
  if (mask & rf::kFieldSequence) rf::put_varint(out, delta(b.sequence, a.sequence + 1));
  if (mask & rf::kFieldViewTick) {
    rf::put_varint(out, delta(b.view_tick, rf::expected_view_tick(a.view_tick)));
  }
  if (mask & rf::kFieldWeaponSlot) rf::put_varint(out, b.weapon_slot);
  if (mask & rf::kFieldLatency) rf::put_varint(out, delta(now.latency_us, before.latency_us));
}

void put_event(std::vector<std::uint8_t>& out, const RecordedEvent& event) {
  out.push_back(static_cast<std::uint8_t>(event.kind));
  if (event.kind == RecordedEventKind::End) {
    rf::put_varint(out, event.end_reason);
    return;
  }
  rf::put_varint(out, event.account);
  if (event.kind == RecordedEventKind::Connect) rf::put_string(out, event.name);
}

}  // namespace

bool bit_identical(const RecordedInput& a, const RecordedInput& b) {
  const PlayerInput& x = a.input;
  const PlayerInput& y = b.input;
  return a.entity_id == b.entity_id && a.latency_us == b.latency_us && x.sequence == y.sequence &&
         same_bits(x.move_right, y.move_right) && same_bits(x.move_forward, y.move_forward) &&
         same_bits(x.yaw_rad, y.yaw_rad) && same_bits(x.pitch_rad, y.pitch_rad) &&
         x.buttons == y.buttons && x.weapon_slot == y.weapon_slot && x.view_tick == y.view_tick &&
         x.view_fraction == y.view_fraction;
}

RecordingWriter::RecordingWriter(RecordingHeader header, std::size_t max_bytes)
    : max_bytes_(max_bytes) {
  framed_.assign(rf::kMagic.begin(), rf::kMagic.end());
  framed_.push_back(rf::kVersion);
  std::vector<std::uint8_t> payload;
  rf::put_string(payload, header.server_version);
  rf::put_varint(payload, header.map_files.size());
  for (const RecordedFile& file : header.map_files) {
    rf::put_string(payload, file.path);
    rf::put_string(payload, file.text);
  }
  rf::put_varint(payload, header.config.size());
  rf::put_bytes(payload, header.config);
  rf::put_u64(payload, header.seed);
  rf::put_varint(payload, header.hash_interval_ticks);
  rf::put_varint(payload, header.tick_rate_hz);
  rf::put_chunk(framed_, rf::kChunkHeader, payload);
  append(framed_);
  if (std::string error = rf::check_header(header); !error.empty()) {
    stop("the header is not recordable: " + error);
  }
}

void RecordingWriter::stop(std::string reason) {
  if (stopped_reason_.empty()) stopped_reason_ = std::move(reason);
  has_pending_ = false;
  open_ = false;
}

void RecordingWriter::begin_tick(std::uint32_t tick) {
  if (finished_ || full()) return;
  if (has_pending_) encode_pending();
  if (full()) return;
  if (tick <= last_tick_) {
    std::string reason = "tick ";
    reason += std::to_string(tick) + " began after tick " + std::to_string(last_tick_);
    stop(std::move(reason));
    return;
  }
  pending_.tick = tick;
  pending_.events.clear();
  pending_.inputs.clear();
  pending_has_hash_ = false;
  has_pending_ = true;
  open_ = true;
  last_tick_ = tick;
}

void RecordingWriter::add_event(const RecordedEvent& event) {
  if (finished_ || full()) return;
  std::string reason;
  if (!open_) {
    reason = "an event outside begin_tick/end_tick";
  } else if (pending_.events.size() == kMaxRecordedEventsPerTick) {
    reason = "more than ";
    reason += std::to_string(kMaxRecordedEventsPerTick) + " events in tick " +
              std::to_string(pending_.tick);
  } else {
    reason = rf::check_event(event);
  }
  if (!reason.empty()) return stop(std::move(reason));
  pending_.events.push_back(event);
}

void RecordingWriter::add_input(const RecordedInput& input) {
  if (finished_ || full()) return;
  std::string reason;
  const bool seen =
      std::any_of(pending_.inputs.begin(), pending_.inputs.end(),
                  [&](const RecordedInput& other) { return other.entity_id == input.entity_id; });
  if (!open_) {
    reason = "an input outside begin_tick/end_tick";
  } else if (pending_.inputs.size() == kMaxRecordedPlayers) {
    reason = "more than ";
    reason +=
        std::to_string(kMaxRecordedPlayers) + " inputs in tick " + std::to_string(pending_.tick);
  } else if (seen) {
    reason = "a second input of entity ";
    reason += std::to_string(input.entity_id) + " in tick " + std::to_string(pending_.tick);
  } else if (std::string error = rf::check_input(input.input); !error.empty()) {
    reason = "entity ";
    reason += std::to_string(input.entity_id) + " in tick " + std::to_string(pending_.tick) + ": " +
              error;
  }
  if (!reason.empty()) return stop(std::move(reason));
  pending_.inputs.push_back(input);
}

void RecordingWriter::add_hash(std::uint32_t tick, std::uint64_t hash) {
  if (finished_ || full()) return;
  if (!has_pending_ || tick != pending_.tick) {
    begin_tick(tick);
    open_ = false;
    if (full()) return;
  }
  pending_hash_ = hash;
  pending_has_hash_ = true;
}

void RecordingWriter::end_tick() {
  open_ = false;
}

std::size_t RecordingWriter::bytes() const {
  return file_bytes_ + chunk_.size();
}

void RecordingWriter::append(std::span<const std::uint8_t> bytes) {
  if (blocks_.empty() || blocks_.back().capacity() - blocks_.back().size() < bytes.size()) {
    blocks_.emplace_back().reserve(std::max(kBlockBytes, bytes.size()));
  }
  blocks_.back().insert(blocks_.back().end(), bytes.begin(), bytes.end());
  file_bytes_ += bytes.size();
  file_crc_ = rf::crc32(bytes, file_crc_);
}

void RecordingWriter::encode_pending() {
  has_pending_ = false;
  record_.clear();
  std::uint32_t flags = 0;
  if (!pending_.events.empty()) flags |= rf::kTickEvents;
  const bool same_entities = std::equal(
      pending_.inputs.begin(), pending_.inputs.end(), previous_entities_.begin(),
      previous_entities_.end(),
      [](const RecordedInput& input, std::uint32_t id) { return input.entity_id == id; });
  if (!same_entities) flags |= rf::kTickEntities;
  const auto previous = [&](std::uint32_t id) {
    return std::lower_bound(
        previous_inputs_.begin(), previous_inputs_.end(), id,
        [](const RecordedInput& input, std::uint32_t key) { return input.entity_id < key; });
  };
  changes_.clear();
  bool any_change = false;
  for (const RecordedInput& input : pending_.inputs) {
    const auto it = previous(input.entity_id);
    RecordedInput before;
    before.entity_id = input.entity_id;
    if (it != previous_inputs_.end() && it->entity_id == input.entity_id) before = *it;
    const std::size_t at = changes_.size();
    put_input_change(changes_, before, input);
    any_change = any_change || changes_.size() != at + 1 || changes_[at] != 0;
  }
  if (any_change) flags |= rf::kTickChanges;
  if (pending_has_hash_) flags |= rf::kTickHash;

  rf::put_varint(
      record_,
      (static_cast<std::uint64_t>(pending_.tick - last_encoded_) << rf::kTickFlagBits) | flags);
  if (flags & rf::kTickEvents) {
    rf::put_varint(record_, pending_.events.size());
    for (const RecordedEvent& event : pending_.events) put_event(record_, event);
  }
  if (flags & rf::kTickEntities) {
    rf::put_varint(record_, pending_.inputs.size());
    for (const RecordedInput& input : pending_.inputs) rf::put_varint(record_, input.entity_id);
  }
  if (flags & rf::kTickChanges) rf::put_bytes(record_, changes_);
  if (flags & rf::kTickHash) rf::put_u64(record_, pending_hash_);

  if (file_bytes_ + chunk_.size() + record_.size() + kFinishReserve > max_bytes_) {
    std::string reason = "the recording reached its limit of ";
    reason += std::to_string(max_bytes_) + " bytes at tick " + std::to_string(pending_.tick);
    stop(std::move(reason));
    return;
  }
  rf::put_bytes(chunk_, record_);
  last_encoded_ = pending_.tick;
  previous_entities_.clear();
  for (const RecordedInput& input : pending_.inputs) {
    previous_entities_.push_back(input.entity_id);
    const auto it = previous(input.entity_id);
    if (it != previous_inputs_.end() && it->entity_id == input.entity_id) {
      *it = input;
    } else {
      previous_inputs_.insert(it, input);
    }
  }
  for (const RecordedEvent& event : pending_.events) {
    if (event.kind != RecordedEventKind::Connect) continue;
    const auto at = std::lower_bound(accounts_.begin(), accounts_.end(), event.account);
    if (at == accounts_.end() || *at != event.account) accounts_.insert(at, event.account);
  }
  ++tick_count_;
  event_count_ += pending_.events.size();
  input_count_ += pending_.inputs.size();
  hash_count_ += pending_has_hash_ ? 1 : 0;
  if (chunk_.size() >= rf::kTickChunkTarget) flush_chunk();
}

void RecordingWriter::flush_chunk() {
  if (chunk_.empty()) return;
  framed_.clear();
  rf::put_chunk(framed_, rf::kChunkTicks, chunk_);
  append(framed_);
  chunk_.clear();
  ++chunk_count_;
}

std::vector<std::uint8_t> RecordingWriter::take_completed() {
  if (file_bytes_ == taken_bytes_) return {};
  std::vector<std::uint8_t> bytes;
  bytes.reserve(file_bytes_ - taken_bytes_);
  for (const std::vector<std::uint8_t>& block : blocks_) {
    bytes.insert(bytes.end(), block.begin(), block.end());
  }
  taken_bytes_ = file_bytes_;
  // The first block's room is kept for the next chunks; the others go.
  blocks_.resize(1);
  blocks_.front().clear();
  return bytes;
}

std::vector<std::uint8_t> RecordingWriter::finish() {
  if (finished_) return {};
  if (has_pending_ && !full()) encode_pending();
  flush_chunk();
  std::vector<std::uint8_t> footer;
  rf::put_varint(footer, tick_count_);
  rf::put_varint(footer, event_count_);
  rf::put_varint(footer, input_count_);
  rf::put_varint(footer, hash_count_);
  rf::put_varint(footer, last_encoded_);
  rf::put_varint(footer, chunk_count_);
  footer.push_back(full() ? 1 : 0);
  rf::put_varint(footer, accounts_.size());
  rf::put_u32(footer, file_crc_);
  std::vector<std::uint8_t> file;
  file.reserve(file_bytes_ - taken_bytes_ + rf::kFrameBytes + footer.size());
  for (const std::vector<std::uint8_t>& block : blocks_) {
    file.insert(file.end(), block.begin(), block.end());
  }
  blocks_.clear();
  rf::put_chunk(file, rf::kChunkFooter, footer);
  finished_ = true;
  has_pending_ = false;
  open_ = false;
  return file;
}

}  // namespace ricochet::server
