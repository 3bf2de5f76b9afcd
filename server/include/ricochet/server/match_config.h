#pragma once
/// Everything a match is configured with, its validation, and the exact codec a recording
/// carries it in (so a replay runs with the very same numbers).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/proto/quantize.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/lag_compensation.h"
#include "ricochet/server/movement.h"
#include "ricochet/server/rules.h"
#include "ricochet/server/tick_clock.h"
#include "ricochet/server/weapons.h"

namespace ricochet::server {

struct MatchConfig {
  std::uint32_t id = 1;
  std::string name = "match";
  int max_players = 16;                      ///< 1..64
  TickClockConfig tick;                      ///< rate 10..128 Hz (60), catch-up cap
  int snapshot_rate_hz = 60;                 ///< 1..tick.rate_hz: a snapshot every
                                             ///< round(tick / snapshot) ticks
  std::size_t snapshot_budget_bytes = 1100;  ///< serialised ServerPayload, 192..1100
  proto::TimeUs reconnect_grace_us = 30 * proto::kMicrosPerSecond;  ///< 0..300 s
  int history_ticks = 64;  ///< entity states kept (states_at), 1..1024
  MovementConfig movement;
  InputBufferConfig input;
  /// Quantisation of the snapshots; its bounds are replaced by the map's and its tick_s by the
  /// tick rate's.
  proto::QuantizationSpec quantization;
  RulesConfig rules;
  WeaponsConfig weapons;
  LagCompensationConfig lag;
  bool record = true;                           ///< keep a recording (recording.h)
  int hash_interval_ticks = 60;                 ///< the match hash every N steps, 1..3600
  std::size_t max_recording_bytes = 64u << 20;  ///< 4 KiB..1 GiB; beyond it recording stops
  /// The snapshot encode cache's layers (all on; match-bench switches them off to measure
  /// them). The bytes sent are the same whatever they are, so recordings leave them out.
  proto::SnapshotCacheLayers snapshot_cache_layers;

  /// Empty when valid; otherwise names the field, the allowed range and what came.
  std::string validate() const;
};

/// The config as bytes: "key value" lines, floats as exact hexadecimal (%a), for recordings.
std::vector<std::uint8_t> encode_match_config(const MatchConfig& config);
/// The inverse; refuses unknown or missing keys, bad numbers and an invalid result, naming it.
std::variant<MatchConfig, std::string> decode_match_config(std::span<const std::uint8_t> bytes);

/// Printable UTF-8: well-formed sequences (no overlongs, surrogates or values past U+10FFFF) and
/// no C0 or C1 control characters.
bool is_printable_utf8(std::string_view text);

}  // namespace ricochet::server
