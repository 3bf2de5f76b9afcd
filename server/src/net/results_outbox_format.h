#pragma once
/// The bytes of one results outbox file (results_outbox.h): one ended match's record, as the
/// server keeps it on local disk until the database has it. Not wire: only this server reads it
/// back. Every integer is little-endian; a double is its IEEE 754 bits as a u64.
///
///   magic    "RCOUTBOX" (8 bytes)
///   version  u16, kOutboxVersion
///   length   u32, bytes of the payload, at most kMaxOutboxPayloadBytes
///   crc      u32, CRC-32 (IEEE, as zlib's) of the payload
///   payload:
///     uuid          32 bytes, lowercase hex (db::is_match_uuid)
///     match id      u32, the server's number of the match (for logs)
///     started_ms    i64, ended_ms i64 (Unix ms), tick_rate i32 (Hz)
///     aborted       u8, 0 or 1
///     team scores   i32 red, i32 blue
///     map           u8 length, then its bytes; mode the same ("ffa" or "tdm")
///     players       u16 count (1..kMaxOutboxPlayers), then each: account i64, team i32,
///                   kills i32, deaths i32, score i32, shots i32, hits i32, damage_dealt f64,
///                   damage_taken f64, seconds_played f64 (hit points, seconds)
///   nothing after the payload.
///
/// decode_outbox_record checks every length, count and value range before use and says what is
/// wrong ("truncated: ...", "CRC-32 mismatch ...", "trailing bytes ..."); whether the record is a
/// valid match is the match rules' business (db::Matches), which refuse it on delivery.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ricochet/db/records.h"

namespace ricochet::server {

inline constexpr std::array<std::uint8_t, 8> kOutboxMagic = {'R', 'C', 'O', 'U',
                                                             'T', 'B', 'O', 'X'};
inline constexpr std::uint16_t kOutboxVersion = 1;
/// magic, version, length, crc.
inline constexpr std::size_t kOutboxHeaderBytes = 8 + 2 + 4 + 4;
/// Players a kept record may hold: far above any match's seats.
inline constexpr std::size_t kMaxOutboxPlayers = 1024;
/// The payload of kMaxOutboxPlayers players with a map and mode of 255 bytes each fits.
inline constexpr std::size_t kMaxOutboxPayloadBytes = 128 * 1024;
/// A file larger than this is not read at all.
inline constexpr std::size_t kMaxOutboxFileBytes = kOutboxHeaderBytes + kMaxOutboxPayloadBytes;

/// One kept match record.
struct OutboxRecord {
  std::uint32_t match_id = 0;  ///< the ending server's match number, for logs
  db::MatchRecord record;      ///< with its uuid
};

/// The file's bytes. The record's map and mode must fit in 255 bytes each and its players in
/// kMaxOutboxPlayers (the server's records always do: map names are at most 64 bytes).
std::vector<std::uint8_t> encode_outbox_record(const OutboxRecord& record);

/// What decode_outbox_record found: a record, or why the bytes are not one.
struct DecodedOutbox {
  bool ok = false;
  OutboxRecord record;  ///< when ok
  std::string problem;  ///< when not ok
};

DecodedOutbox decode_outbox_record(std::span<const std::uint8_t> bytes);

}  // namespace ricochet::server
