/// Helpers of the recording byte layout (recording_format.h): CRC-32, varints, chunk framing and
/// the value checks the writer and the reader share.

#include "recording_format.h"

#include <cmath>

#include "ricochet/proto/weapon_wire.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server::recording_format {

namespace {

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), as zlib's crc32().
constexpr std::array<std::uint32_t, 256> make_crc_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}
constexpr std::array<std::uint32_t, 256> kCrcTable = make_crc_table();

/// |move| after validate_input()'s normalisation, with float rounding.
constexpr float kMaxMoveLengthSq = 1.0f + 1e-5f;

}  // namespace

const char* chunk_name(std::uint8_t type) {
  switch (type) {
    case kChunkHeader:
      return "header";
    case kChunkTicks:
      return "ticks";
    case kChunkFooter:
      return "footer";
    default:
      return "unknown";
  }
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc) {
  crc = ~crc;
  for (const std::uint8_t byte : bytes) crc = kCrcTable[(crc ^ byte) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void put_varint(std::vector<std::uint8_t>& out, std::uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<std::uint8_t>(value | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<std::uint8_t>(value));
}

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

void put_u64(std::vector<std::uint8_t>& out, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

void put_bytes(std::vector<std::uint8_t>& out, std::span<const std::uint8_t> bytes) {
  out.insert(out.end(), bytes.begin(), bytes.end());
}

void put_string(std::vector<std::uint8_t>& out, const std::string& text) {
  put_varint(out, text.size());
  out.insert(out.end(), text.begin(), text.end());
}

void put_chunk(std::vector<std::uint8_t>& out, std::uint8_t type,
               std::span<const std::uint8_t> payload) {
  const std::size_t head = out.size();
  out.push_back(type);
  put_u32(out, static_cast<std::uint32_t>(payload.size()));
  put_u32(out, crc32(std::span(out).subspan(head, 5)));
  put_bytes(out, payload);
  put_u32(out, crc32(payload));
}

std::string check_header(const RecordingHeader& header) {
  std::string error;
  if (header.server_version.size() > kMaxRecordedVersionBytes) {
    error = "server_version must be at most ";
    error += std::to_string(kMaxRecordedVersionBytes) + " bytes, got " +
             std::to_string(header.server_version.size());
  } else if (header.map_files.size() > kMaxRecordedMapFiles) {
    error = "at most ";
    error += std::to_string(kMaxRecordedMapFiles) + " map files, got " +
             std::to_string(header.map_files.size());
  } else if (header.config.size() > kMaxRecordedConfigBytes) {
    error = "config must be at most ";
    error += std::to_string(kMaxRecordedConfigBytes) + " bytes, got " +
             std::to_string(header.config.size());
  } else if (header.hash_interval_ticks > kMaxHashInterval) {
    error = "hash_interval_ticks must be 0..";
    error +=
        std::to_string(kMaxHashInterval) + ", got " + std::to_string(header.hash_interval_ticks);
  } else if (header.tick_rate_hz < 1 || header.tick_rate_hz > kMaxTickRate) {
    error = "tick_rate_hz must be 1..";
    error += std::to_string(kMaxTickRate) + ", got " + std::to_string(header.tick_rate_hz);
  }
  if (!error.empty()) return error;
  for (std::size_t i = 0; i < header.map_files.size(); ++i) {
    const RecordedFile& file = header.map_files[i];
    if (file.path.empty() || file.path.size() > kMaxRecordedPathBytes) {
      error = "map file ";
      error += std::to_string(i) + ": path must be 1.." + std::to_string(kMaxRecordedPathBytes) +
               " bytes, got " + std::to_string(file.path.size());
      return error;
    }
    if (file.text.size() > kMaxRecordedMapFileBytes) {
      error = "map file ";
      error += std::to_string(i) + " (" + file.path + ") must be at most " +
               std::to_string(kMaxRecordedMapFileBytes) + " bytes, got " +
               std::to_string(file.text.size());
      return error;
    }
  }
  return error;
}

std::string check_input(const PlayerInput& input) {
  const auto finite = [](float value) { return std::isfinite(value); };
  if (!finite(input.move_right) || !finite(input.move_forward) || !finite(input.yaw_rad) ||
      !finite(input.pitch_rad)) {
    return "a move or view component is not finite";
  }
  if (std::abs(input.move_right) > 1 || std::abs(input.move_forward) > 1 ||
      input.move_right * input.move_right + input.move_forward * input.move_forward >
          kMaxMoveLengthSq) {
    return "move (right, forward) must be a vector of length <= 1";
  }
  if (std::abs(input.yaw_rad) > proto::kMaxYawRad) return "yaw must be within -2pi..2pi rad";
  if (std::abs(input.pitch_rad) > kAcceptedMaxPitchRad) {
    return "pitch must be within -pi/2..pi/2 rad";
  }
  if ((input.buttons & ~proto::kKnownButtons) != 0) {
    std::string error = "unknown button bits ";
    error += std::to_string(input.buttons & ~proto::kKnownButtons);
    return error;
  }
  if (input.weapon_slot > proto::kMaxWeaponSlot) {
    std::string error = "weapon_slot must be 0..";
    error += std::to_string(proto::kMaxWeaponSlot) + ", got " + std::to_string(input.weapon_slot);
    return error;
  }
  return {};
}

std::string check_event(const RecordedEvent& event) {
  const auto kind = static_cast<unsigned>(event.kind);
  if (kind < static_cast<unsigned>(RecordedEventKind::Connect) ||
      kind > static_cast<unsigned>(RecordedEventKind::End)) {
    std::string error = "event kind must be 1..5, got ";
    error += std::to_string(kind);
    return error;
  }
  if (event.kind == RecordedEventKind::Connect &&
      (event.name.empty() || event.name.size() > kMaxRecordedNameBytes)) {
    std::string error = "a connect's name must be 1..";
    error +=
        std::to_string(kMaxRecordedNameBytes) + " bytes, got " + std::to_string(event.name.size());
    return error;
  }
  if (event.kind == RecordedEventKind::End &&
      !wire::MatchEndReason_IsValid(static_cast<int>(event.end_reason))) {
    std::string error = "end reason must be a MatchEndReason, got ";
    error += std::to_string(event.end_reason);
    return error;
  }
  return {};
}

}  // namespace ricochet::server::recording_format
