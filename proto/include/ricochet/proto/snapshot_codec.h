#pragma once
/// Delta-compressed snapshots (PROTOCOL.md Snapshots): per client, the server encodes the
/// quantised state of every entity against the newest snapshot that client acknowledged, within
/// a byte budget; the client decodes, validates and echoes the newest tick it decoded.
///
/// An entity whose state equals the baseline's costs nothing but its share of a run length; a
/// changed one costs its position, velocity, orientation and flag deltas in Exp-Golomb codes
/// whose orders the encoder picks per snapshot. When the budget is short, entities are sent in
/// priority order (nearest to the viewer and most changed first); one left out accumulates
/// priority and goes sooner next time, and the client keeps showing its baseline state.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/quantize.h"
#include "ricochet/wire/snapshot.pb.h"

namespace ricochet::proto {

class DeltaTable;  // the encoder's private parts (src/)
class EncodePass;

/// Snapshots remembered per client, on either end, unless the options say otherwise. At 60 Hz
/// it covers about a second of acknowledgement delay.
inline constexpr std::size_t kDefaultSnapshotRing = 64;
/// Largest packed entity stream a decoder accepts, bytes (a game packet is at most 1200 bytes).
inline constexpr std::size_t kMaxSnapshotStreamBytes = 1200;

struct SnapshotEncoderOptions {
  /// Sent snapshots remembered as possible baselines, 2..1024.
  std::size_t ring_size = kDefaultSnapshotRing;
  /// Priority falls off with distance d from the viewer as 1 / (1 + d / distance_scale_m).
  float distance_scale_m = 8.0f;

  /// Empty when usable; otherwise names the wrong field, its range and its value.
  std::string validate() const;
};

/// What the last SnapshotEncoder::encode did, for benches and metrics.
struct SnapshotEncodeReport {
  bool has_baseline = false;
  std::uint32_t baseline_tick = 0;
  std::uint32_t entities = 0;  ///< in the world this tick
  std::uint32_t pending = 0;   ///< entities differing from the baseline (changed, new or gone)
  std::uint32_t sent = 0;      ///< of those, in the snapshot
  std::uint32_t deferred = 0;  ///< of those, left out for the budget
  std::size_t bytes = 0;       ///< serialised wire::Snapshot
};

/// Work the encoders of one match share within a tick. The match makes one and passes it to
/// every client's SnapshotEncoder::encode of a tick, with the same world each time. A client
/// sent everything holds the world of that tick, which the cache names by a token; a client
/// whose baseline is such a world (or who has none), as old as that of a client encoded before
/// it this tick, and for whom everything pending fits the budget, is sent a copy of that
/// client's stream instead of encoding it again. Any other client is encoded as usual, except
/// that a changed entity whose baseline state and age another client of the tick had reuses
/// that client's delta, and its bits when the field orders agree; and that a client left
/// something out holds that tick's world but for those entities, so that later its baseline's
/// differences come from one walk of the world against that world, with only the entities it
/// holds otherwise compared. A tick's world is copied once and shared by every client left
/// holding it (not copied per client). Either way the bytes are the ones encode writes without
/// the cache. Allocates nothing once its buffers have grown to the world's size and its worlds
/// to the ticks the clients hold. Each sharing layer can be switched off (SnapshotCacheLayers);
/// src/snapshot_encode_cache.cpp's table says what invalidates each and what it saves.
/// The sharing layers of a SnapshotEncodeCache, each of which can be switched off (to measure
/// what it saves, or to test the others alone); the bytes are the same whatever the switches.
struct SnapshotCacheLayers {
  /// A client whose baseline and age another client of the tick had, and for whom everything
  /// fits, is sent a copy of that client's stream.
  bool streams = true;
  /// Clients holding the same baseline state of an entity at the same age share its delta, its
  /// fields' bits per set of orders and the order tallies; a new entity is written once.
  bool deltas = true;
  /// A client sent the world but for a few entities holds the tick's one shared copy of it and
  /// those exceptions, instead of a view of its own. (A client sent all of it always holds the
  /// shared copy, by which streams and walks know its baseline.)
  bool world_baselines = true;
  /// Clients whose baseline is such a world follow one walk of the world against it instead of
  /// comparing every entity. Needs deltas.
  bool walks = true;
  /// Followers of a walk start from what its first follower holding the whole world found and
  /// estimated, edited at their exceptions. Needs walks.
  bool whole_world_start = true;
};

/// Switches off the layer named `name` ("streams", "deltas", "world_baselines", "walks",
/// "whole_world_start"; "all" for every one) in `layers`. False when `name` is none of those.
bool switch_off_cache_layer(std::string_view name, SnapshotCacheLayers& layers);

class SnapshotEncodeCache {
 public:
  /// max_streams: distinct (baseline, age) streams remembered per tick, 1..64; past that the
  /// oldest is replaced.
  explicit SnapshotEncodeCache(SnapshotCacheLayers layers = {}, std::size_t max_streams = 4);
  SnapshotEncodeCache(SnapshotEncodeCache&&) noexcept;
  SnapshotEncodeCache& operator=(SnapshotEncodeCache&&) noexcept;
  ~SnapshotEncodeCache();

  /// Encodes answered with a copy, and encodes that wrote their own stream, since construction.
  std::uint64_t hits() const { return hits_; }
  std::uint64_t misses() const { return misses_; }
  /// Of the misses, those whose baseline was a world the cache saw but for a few entities, and
  /// so followed that world's walk instead of comparing every entity with their baseline.
  std::uint64_t walks_followed() const { return walks_followed_; }

 private:
  friend class SnapshotEncoder;
  struct Streams;
  std::unique_ptr<Streams> streams_;
  SnapshotCacheLayers layers_;
  std::uint64_t hits_ = 0;
  std::uint64_t misses_ = 0;
  std::uint64_t walks_followed_ = 0;
};

class SnapshotEncoder {
 public:
  /// spec and options must be valid (their validate() empty).
  explicit SnapshotEncoder(QuantizationSpec spec, SnapshotEncoderOptions options = {});
  SnapshotEncoder(SnapshotEncoder&&) noexcept;
  SnapshotEncoder& operator=(SnapshotEncoder&&) noexcept;
  ~SnapshotEncoder();

  /// world: this tick's entities sorted by id, ids unique. viewer_m: the client's position for
  /// priority. Fills `out` so that out.ByteSizeLong() <= budget_bytes (which must be >= 16; at
  /// most about 1100 so the packet fits 1200 bytes). Ticks must increase from call to call.
  void encode(std::uint32_t tick, std::span<const QuantizedEntity> world,
              std::array<float, 3> viewer_m, std::size_t budget_bytes, wire::Snapshot& out);
  /// The same, sharing work with the other encoders of the tick through `cache` (which every
  /// encoder passed it must share this encoder's spec; `world` must not change between the
  /// calls of one tick). Writes exactly what the call without the cache writes.
  void encode(std::uint32_t tick, std::span<const QuantizedEntity> world,
              std::array<float, 3> viewer_m, std::size_t budget_bytes, wire::Snapshot& out,
              SnapshotEncodeCache& cache);

  /// From ClientPayload.ack_snapshot_tick (untrusted): a tick this encoder sent and still
  /// remembers, newer than the current baseline, becomes the baseline; anything else is ignored
  /// and counted.
  void acknowledge(std::uint32_t tick);

  const SnapshotEncodeReport& last_report() const { return report_; }
  /// Acknowledgements that named a tick not in the ring, or not newer than the baseline.
  std::uint64_t ignored_acks() const { return ignored_acks_; }
  const QuantizationSpec& spec() const { return spec_; }

 private:
  /// What the client holds after decoding a snapshot. With world_token 0 it is `view`.
  /// Otherwise it is the world a SnapshotEncodeCache saw under that token, `world` (one copy,
  /// shared by every client sent it), but for the entities at that world's indices `held`
  /// (sorted), which the client holds at the older `held_states`, and `absent` (sorted), which
  /// it does not hold.
  struct Sent {
    bool valid = false;
    std::uint32_t tick = 0;
    std::vector<QuantizedEntity> view;
    std::uint64_t world_token = 0;
    std::shared_ptr<const std::vector<QuantizedEntity>> world;
    std::vector<std::uint32_t> held, absent;
    std::vector<QuantizedEntity> held_states;
  };
  Sent& slot(std::uint32_t tick) { return ring_[tick % ring_.size()]; }

  // An encode's steps (src/snapshot_encode_pass.h defines their types).
  struct Baseline;
  struct Budget;
  struct Outcome;
  struct Scratch;
  friend struct SnapshotEncodeCache::Streams;
  void encode_with(std::uint32_t tick, std::span<const QuantizedEntity> world,
                   std::array<float, 3> viewer_m, std::size_t budget_bytes, wire::Snapshot& out,
                   SnapshotEncodeCache* cache);
  Baseline acked_baseline(std::uint32_t tick);
  static Budget stream_budget(std::uint32_t tick, std::uint32_t baseline_age,
                              std::size_t budget_bytes);
  /// The plain encode: every difference from the baseline found, estimated, selected, written.
  Outcome encode_against(const Baseline& baseline, DeltaTable& deltas,
                         std::span<const QuantizedEntity> world, std::array<float, 3> viewer_m,
                         const Budget& budget, wire::Snapshot& out);
  /// Selects, writes and lists what the client will hold, after the pass found and estimated.
  Outcome finish(EncodePass& pass, const Baseline& baseline, const Budget& budget,
                 wire::Snapshot& out);
  void remember_sent(std::uint32_t tick, std::span<const QuantizedEntity> world, Outcome& outcome);
  // The cache's paths (src/snapshot_encode_cache.cpp): a copy of another client's stream, a
  // walk followed, or the plain encode with shared deltas.
  Outcome encode_cached(const Baseline& baseline, std::uint32_t tick,
                        std::span<const QuantizedEntity> world, std::array<float, 3> viewer_m,
                        const Budget& budget, wire::Snapshot& out, SnapshotEncodeCache& cache);
  Outcome follow_walk(const Baseline& baseline, std::span<const QuantizedEntity> world,
                      std::array<float, 3> viewer_m, const Budget& budget, wire::Snapshot& out,
                      SnapshotEncodeCache& cache);

  QuantizationSpec spec_;
  SnapshotEncoderOptions options_;
  std::vector<Sent> ring_;
  bool has_ack_ = false;
  std::uint32_t acked_tick_ = 0;
  bool has_sent_ = false;
  std::uint32_t last_tick_ = 0;
  /// Accumulated priority of the entities left out last time, sorted by id.
  std::vector<std::pair<std::uint32_t, float>> priority_;
  std::vector<QuantizedEntity> next_view_;
  std::vector<std::uint32_t> next_held_, next_absent_;
  std::vector<QuantizedEntity> next_held_states_;
  BitWriter stream_;
  std::unique_ptr<Scratch> scratch_;
  SnapshotEncodeReport report_;
  std::uint64_t ignored_acks_ = 0;
};

/// Why a decoder refused a snapshot. Every refusal leaves the decoder as it was.
enum class SnapshotRejection : std::uint8_t {
  Oversized,          ///< entity stream longer than kMaxSnapshotStreamBytes
  Stale,              ///< tick not newer than the newest decoded one
  BaselineAfterTick,  ///< baseline_age greater than tick
  UnknownBaseline,    ///< baseline tick not (or no longer) in the ring
  Truncated,          ///< the stream ended inside a field
  BadCode,            ///< an Exp-Golomb prefix too long, or a count beyond any sane size
  RemovedOutOfRange,  ///< a removal names an index past the baseline's entities
  IdOutOfOrder,       ///< a new entity's id overflows or is already held
  TooManyEntities,    ///< more entities than the decoder's limit
  ChangedOutOfRange,  ///< a change names an index past the kept entities
  EmptyChange,        ///< a changed entity with no changed field
  ValueOutOfRange,    ///< a position, velocity or orientation outside the spec's ranges
  TrailingBits,       ///< bits after the last field beyond the zero padding of the last byte
  kCount,
};
const char* name(SnapshotRejection reason);

struct SnapshotDecoderOptions {
  std::size_t ring_size = kDefaultSnapshotRing;  ///< decoded snapshots kept as baselines, 2..1024
  std::uint32_t max_entities = 65536;            ///< larger entity sets are refused

  std::string validate() const;
};

struct SnapshotDecodeResult {
  bool ok = false;
  SnapshotRejection reason = SnapshotRejection::kCount;  ///< when !ok
  std::string message;                                   ///< when !ok: expected and got
  std::uint32_t tick = 0;
  /// When ok: every entity the client holds at `tick`, sorted by id. Valid until the next
  /// decode call.
  std::span<const QuantizedEntity> entities;
};

class SnapshotDecoder {
 public:
  /// spec must equal the encoder's; spec and options must be valid.
  explicit SnapshotDecoder(QuantizationSpec spec, SnapshotDecoderOptions options = {});

  /// Validates everything; a refusal is counted by reason and changes nothing.
  SnapshotDecodeResult decode(const wire::Snapshot& in);

  bool has_snapshot() const { return has_newest_; }
  /// What the client echoes as ack_snapshot_tick (meaningful once has_snapshot()).
  std::uint32_t newest_tick() const { return newest_tick_; }
  std::uint64_t accepted() const { return accepted_; }
  const std::array<std::uint64_t, static_cast<std::size_t>(SnapshotRejection::kCount)>& rejections()
      const {
    return rejections_;
  }

 private:
  struct Decoded {
    bool valid = false;
    std::uint32_t tick = 0;
    std::vector<QuantizedEntity> view;
  };

  QuantizationSpec spec_;
  SnapshotDecoderOptions options_;
  std::vector<Decoded> ring_;
  std::vector<QuantizedEntity> view_;  ///< the snapshot being decoded
  /// The stream reader's working sets, kept so that a decode allocates nothing once they and
  /// the ring's views have grown.
  std::vector<QuantizedEntity> kept_;
  std::vector<QuantizedEntity> added_;
  std::vector<std::uint8_t> removed_;
  bool has_newest_ = false;
  std::uint32_t newest_tick_ = 0;
  std::uint64_t accepted_ = 0;
  std::array<std::uint64_t, static_cast<std::size_t>(SnapshotRejection::kCount)> rejections_{};
};

}  // namespace ricochet::proto
