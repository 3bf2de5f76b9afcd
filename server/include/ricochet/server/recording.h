#pragma once
/// Match recordings: everything needed to re-simulate a match (the map files, the config, the
/// seed, every membership change and every input applied per tick) plus the world's state hash
/// every N ticks to check the re-simulation against. The byte layout is in server/RECORDING.md.
///
/// The Match owns a RecordingWriter that encodes into memory as the ticks go, bounded by
/// max_bytes; the server takes each completed chunk off the match strand and appends it to a
/// file in progress (RecordingFiles), so a crash keeps everything up to the last chunk written.
/// read_recording() decodes a file without trusting any of it.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/server/input_buffer.h"

namespace ricochet::server {

/// Largest values read_recording() accepts (and the writer must stay within).
inline constexpr std::uint64_t kMaxRecordingBytes = 1ull << 30;  ///< 1 GiB file
inline constexpr std::size_t kMaxRecordedPlayers = 64;           ///< inputs per tick
inline constexpr std::size_t kMaxRecordedEventsPerTick = 256;
inline constexpr std::size_t kMaxRecordedNameBytes = 32;  ///< Connect's name
inline constexpr std::size_t kMaxRecordedMapFiles = 64;
inline constexpr std::size_t kMaxRecordedMapFileBytes = 2u << 20;  ///< 2 MiB per file
inline constexpr std::size_t kMaxRecordedPathBytes = 1024;
inline constexpr std::size_t kMaxRecordedConfigBytes = 1u << 20;  ///< 1 MiB
inline constexpr std::size_t kMaxRecordedVersionBytes = 64;

/// One file the map was loaded from (the map first, then what it references, by path).
struct RecordedFile {
  std::string path;
  std::string text;
};

enum class RecordedEventKind : std::uint8_t {
  Connect = 1,     ///< account, name
  Disconnect = 2,  ///< account: its game connection is gone (the entity waits the grace)
  Leave = 3,       ///< account: gone for good
  TimedOut = 4,    ///< account: its reconnect grace ran out
  End = 5,         ///< end_reason
};

/// A membership change, applied before the tick's step. Only the fields the kind names are
/// recorded; the others read back as their defaults.
struct RecordedEvent {
  RecordedEventKind kind = RecordedEventKind::Connect;
  std::uint64_t account = 0;     ///< every kind but End
  std::string name;              ///< Connect only, at most kMaxRecordedNameBytes
  std::uint32_t end_reason = 0;  ///< End only: a wire::MatchEndReason
};

/// The input one player entity stepped with.
struct RecordedInput {
  std::uint32_t entity_id = 0;
  PlayerInput input;             ///< in the ranges validate_input() enforces (sequence may be 0)
  std::uint32_t latency_us = 0;  ///< the one-way latency estimate used for this input, µs
};

/// Every field equal, floats bit for bit (so -0 differs from 0 and a NaN equals itself): what a
/// recording must give back.
bool bit_identical(const RecordedInput& a, const RecordedInput& b);

struct RecordedTick {
  std::uint32_t tick = 0;             ///< the step number this becomes (1, 2, ...)
  std::vector<RecordedEvent> events;  ///< applied before this step, in order
  std::vector<RecordedInput> inputs;  ///< one per player entity that steps with an input;
                                      ///< distinct entity ids
};

/// world.state_hash() after step `tick`.
struct RecordedHash {
  std::uint32_t tick = 0;
  std::uint64_t hash = 0;
};

struct RecordingHeader {
  std::string server_version;           ///< at most kMaxRecordedVersionBytes
  std::vector<RecordedFile> map_files;  ///< the map first
  std::vector<std::uint8_t> config;     ///< opaque: the match's MatchConfig codec
  std::uint64_t seed = 0;
  std::uint32_t hash_interval_ticks = 0;  ///< 0: no hashes
  std::uint32_t tick_rate_hz = 60;        ///< 1..1000
};

struct Recording {
  RecordingHeader header;
  std::vector<RecordedTick> ticks;   ///< increasing tick numbers
  std::vector<RecordedHash> hashes;  ///< increasing, each the tick of an entry of `ticks`
  bool complete = false;             ///< the footer was there: nothing is missing at the end
  bool truncated = false;            ///< the writer hit max_bytes and recorded no further ticks
  /// The footer's player count: distinct accounts with a Connect event in `ticks`. None without
  /// a footer (complete = false) or in a version 1 file, whose footer has no such field.
  std::optional<std::uint32_t> players;
  /// complete = false: where the file stops, why, and the last tick it holds ("cut inside chunk
  /// 12 (ticks) at byte 40960 (8 of 16397 bytes there); replayable to tick 3600").
  std::string cut;
  std::uint64_t cut_offset = 0;  ///< complete = false: the byte the readable part ends at
};

/// Encodes a recording into memory as the match goes. Per tick: begin_tick(), its events and
/// inputs, then (before the next begin_tick or finish) add_hash() for that tick if one is due.
/// Ticks must increase; a call out of that order stops the recording (stopped_reason() says
/// why), as does reaching max_bytes: the bytes so far stay a valid recording marked truncated.
class RecordingWriter {
 public:
  /// max_bytes: the size finish() stays within (a header alone larger than that is still
  /// written whole).
  RecordingWriter(RecordingHeader header, std::size_t max_bytes);

  void begin_tick(std::uint32_t tick);
  void add_event(const RecordedEvent& event);
  void add_input(const RecordedInput& input);
  /// The hash after step `tick`: the tick just begun or, if later, a tick of its own with no
  /// events or inputs.
  void add_hash(std::uint32_t tick, std::uint64_t hash);
  void end_tick();

  /// True once the writer stopped recording: over max_bytes, or a call out of order.
  bool full() const { return !stopped_reason_.empty(); }
  const std::string& stopped_reason() const { return stopped_reason_; }
  /// Bytes encoded so far (finish() adds the last chunk's framing and the footer).
  std::size_t bytes() const;
  /// The file's bytes completed since the last take: the magic and header chunk first, then
  /// every tick chunk once it is full (16 KiB). Empty when there are none. Appended one after
  /// the other, and then finish(), they make the file finish() alone would have returned.
  std::vector<std::uint8_t> take_completed();
  /// Writes the last ticks and the footer (totals, players and a checksum) and returns the rest
  /// of the file: all of it when take_completed() was never called. The writer records nothing
  /// after.
  std::vector<std::uint8_t> finish();

 private:
  void encode_pending();
  void flush_chunk();
  /// Appends framed bytes to the file, in blocks that never move (a vector that doubled would
  /// copy the whole recording in one tick: 32 MiB at the 64 MiB limit).
  void append(std::span<const std::uint8_t> bytes);
  void stop(std::string reason);

  std::size_t max_bytes_;
  /// The file so far (less what take_completed() took): magic, header chunk and the full tick
  /// chunks, in blocks of at least kBlockBytes, each filled within the capacity it was made with.
  std::vector<std::vector<std::uint8_t>> blocks_;
  std::size_t file_bytes_ = 0;         ///< in blocks_ and taken
  std::size_t taken_bytes_ = 0;        ///< by take_completed()
  std::uint32_t file_crc_ = 0;         ///< CRC-32 of blocks_, for the footer
  std::vector<std::uint8_t> framed_;   ///< scratch: one framed chunk
  std::vector<std::uint8_t> chunk_;    ///< the tick chunk being filled (payload only)
  std::vector<std::uint8_t> record_;   ///< scratch: one tick record
  std::vector<std::uint8_t> changes_;  ///< scratch: its change masks and fields
  RecordedTick pending_;
  bool has_pending_ = false;  ///< pending_ is a tick not yet encoded
  bool open_ = false;         ///< between begin_tick() and end_tick()
  bool pending_has_hash_ = false;
  std::uint64_t pending_hash_ = 0;
  std::uint32_t last_tick_ = 0;     ///< the last tick begun
  std::uint32_t last_encoded_ = 0;  ///< the last tick in the bytes
  std::vector<std::uint32_t> previous_entities_;
  std::vector<RecordedInput> previous_inputs_;  ///< the last input of every entity, by id
  std::uint64_t tick_count_ = 0, event_count_ = 0, input_count_ = 0, hash_count_ = 0;
  std::vector<std::uint64_t> accounts_;  ///< sorted: every account a recorded Connect named
  std::uint32_t chunk_count_ = 0;
  bool finished_ = false;
  std::string stopped_reason_;
};

/// What is wrong with a recording and where: "truncated at byte 812 in tick 4711 (expected 9
/// more bytes)", "chunk 3 (ticks) at byte 8200: CRC-32 mismatch ...".
struct RecordingError {
  std::string message;
  std::uint64_t offset = 0;  ///< byte in the file
};

/// Decodes and validates a whole recording. A file cut short after its header (also inside the
/// footer) reads as `complete = false` with every whole chunk before the cut and `cut` saying
/// where; a cut inside the magic or the header chunk, a CRC mismatch, a bad length, count or
/// enum is an error.
std::variant<Recording, RecordingError> read_recording(std::span<const std::uint8_t> bytes);

/// For a listing, without reading the ticks: the bytes from the file's start to the end of its
/// header chunk (9 + 13 + the chunk's length), at most kMaxRecordingHeaderBytes.
inline constexpr std::size_t kMaxRecordingHeaderBytes = 8u << 20;
/// How many of the file's first bytes read_recording_header() needs, from the first 13 (the
/// magic, the version and the header chunk's type and length); an error when those are not a
/// recording's or the header chunk is over kMaxRecordingHeaderBytes.
std::variant<std::size_t, RecordingError> recording_header_bytes(
    std::span<const std::uint8_t> first);
/// Decodes and validates the header chunk at the start of `head` (bytes after it are ignored).
std::variant<RecordingHeader, RecordingError> read_recording_header(
    std::span<const std::uint8_t> head);

/// The footer's totals (server/RECORDING.md): what a listing reads from a file's last bytes.
struct RecordingFooter {
  std::uint64_t ticks = 0, events = 0, inputs = 0, hashes = 0, tick_chunks = 0;
  std::uint32_t last_tick = 0;
  bool truncated = false;
  /// Distinct accounts with a Connect event in the file; none in a version 1 footer.
  std::optional<std::uint32_t> players;
};
/// A footer chunk is at most this many bytes, framing included.
inline constexpr std::size_t kMaxRecordingFooterBytes = 77;
/// The footer chunk `tail` (a file's last bytes, at least kMaxRecordingFooterBytes of them or the
/// whole file) ends with, its frame and payload CRCs checked and its fields decoded (a version 1
/// footer, without the player count, too); nothing when it ends with none (a file cut short: no
/// footer) or its fields are out of range (more players than events). Neither the totals against
/// the chunks nor the file's CRC are checked: read_recording() does that.
std::optional<RecordingFooter> read_recording_footer(std::span<const std::uint8_t> tail);

}  // namespace ricochet::server
