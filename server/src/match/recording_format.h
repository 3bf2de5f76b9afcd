#pragma once
/// The byte layout shared by the recording writer and reader (server/RECORDING.md describes it).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ricochet/server/recording.h"

namespace ricochet::server::recording_format {

/// "RCREC\r\n\x1a": a text transfer or a truncation to 7 bits shows in the first bytes.
inline constexpr std::array<std::uint8_t, 8> kMagic = {'R', 'C', 'R', 'E', 'C', '\r', '\n', 0x1a};
/// The version the writer writes; the reader reads kOldestVersion..kVersion (server/RECORDING.md,
/// Versions). 2: the footer counts the players.
inline constexpr std::uint8_t kVersion = 2;
inline constexpr std::uint8_t kOldestVersion = 1;

enum ChunkType : std::uint8_t { kChunkHeader = 1, kChunkTicks = 2, kChunkFooter = 3 };
const char* chunk_name(std::uint8_t type);

/// type u8, payload length u32 LE, CRC-32 of those 5 bytes u32 LE; then the payload and its
/// CRC-32 u32 LE.
inline constexpr std::size_t kFrameHeadBytes = 9;
inline constexpr std::size_t kFrameBytes = kFrameHeadBytes + 4;
/// The writer closes a tick chunk once its payload reaches this; the reader refuses tick
/// chunks over kMaxTickChunkBytes.
inline constexpr std::size_t kTickChunkTarget = 16 * 1024;
inline constexpr std::size_t kMaxTickChunkBytes = 1u << 20;
inline constexpr std::size_t kMaxFooterBytes = 64;
/// The longest footer payload of a file within kMaxRecordingBytes (2^30): the last tick (a u32)
/// and the ticks, events, hashes, chunks and players (each at least a byte of the file) take at
/// most 5 varint bytes, the inputs (up to 64 per tick) 6, then truncated u8 and file_crc u32.
inline constexpr std::size_t kLongestFooterBytes = 6 * 5 + 6 + 1 + 4;
static_assert(kLongestFooterBytes <= kMaxFooterBytes);
static_assert(kMaxRecordingFooterBytes == kFrameBytes + kMaxFooterBytes);
inline constexpr std::uint32_t kMaxHashInterval = 1'000'000;
inline constexpr std::uint32_t kMaxTickRate = 1000;

/// Flags in the low 4 bits of a tick record's first varint; the rest is the tick delta (>= 1).
enum TickFlag : std::uint8_t {
  kTickEvents = 1u << 0,    ///< an event list follows
  kTickEntities = 1u << 1,  ///< the list of entities with an input changed: it follows
  kTickChanges = 1u << 2,   ///< a change mask per entity follows (else all inputs repeat)
  kTickHash = 1u << 3,      ///< the state hash after this tick follows (u64 LE)
};
inline constexpr unsigned kTickFlagBits = 4;

/// Bits of an input's change mask (a varint), in the order the changed fields follow. The
/// seven that change most fit the mask's first byte.
enum InputField : std::uint16_t {
  kFieldYaw = 1u << 0,           ///< f32 bits LE
  kFieldPitch = 1u << 1,         ///< f32 bits LE
  kFieldMoveRight = 1u << 2,     ///< f32 bits LE
  kFieldMoveForward = 1u << 3,   ///< f32 bits LE
  kFieldButtons = 1u << 4,       ///< varint
  kFieldViewFraction = 1u << 5,  ///< u8
  kFieldSequence = 1u << 6,      ///< zigzag varint: sequence - (previous + 1)
  kFieldViewTick = 1u << 7,      ///< zigzag varint: view_tick - expected (previous + 1, or 0
                                 ///< when the previous was 0)
  kFieldWeaponSlot = 1u << 8,    ///< varint
  kFieldLatency = 1u << 9,       ///< zigzag varint: latency_us - previous
};
inline constexpr std::uint32_t kKnownFields = (1u << 10) - 1;

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

void put_varint(std::vector<std::uint8_t>& out, std::uint64_t value);
void put_u32(std::vector<std::uint8_t>& out, std::uint32_t value);
void put_u64(std::vector<std::uint8_t>& out, std::uint64_t value);
void put_bytes(std::vector<std::uint8_t>& out, std::span<const std::uint8_t> bytes);
void put_string(std::vector<std::uint8_t>& out, const std::string& text);  ///< varint length
inline std::uint64_t zigzag(std::int64_t value) {
  return (static_cast<std::uint64_t>(value) << 1) ^ static_cast<std::uint64_t>(value >> 63);
}
inline std::int64_t unzigzag(std::uint64_t value) {
  return static_cast<std::int64_t>(value >> 1) ^ -static_cast<std::int64_t>(value & 1);
}
/// Appends a whole chunk (frame and payload).
void put_chunk(std::vector<std::uint8_t>& out, std::uint8_t type,
               std::span<const std::uint8_t> payload);

/// The view_tick an input is expected to have after `previous`.
inline std::uint32_t expected_view_tick(std::uint32_t previous) {
  return previous == 0 ? 0 : previous + 1;
}

/// Empty when the header is within the caps; otherwise what is not.
std::string check_header(const RecordingHeader& header);
/// Empty when the input is one validate_input() could have produced (sequence 0 allowed).
std::string check_input(const PlayerInput& input);
/// Empty when the event's kind, name and end reason are valid.
std::string check_event(const RecordedEvent& event);

}  // namespace ricochet::server::recording_format
