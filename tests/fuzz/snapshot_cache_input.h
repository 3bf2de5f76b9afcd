#pragma once
/// How snapshot_cache_fuzz reads its input, shared with its seed writer. Every byte string is a
/// valid scene; bytes past the end read as 0, which means "as usual" (clients acknowledge at
/// their delay, budget as set up, the cache used).
///
/// Input format:
///   setup, 4 bytes:
///     [0] bits 0..4 switch cache layers off (streams, deltas, world_baselines, walks,
///         whole_world_start); clients = 1 + (bits 5..7) (1..8)
///     [1] stream slots per tick = 1 + [1] % 4; the acknowledgement delay = 1 + ([1] >> 2) % 6
///     [2..3] the usual budget = 24 + big-endian 16 bits % 1077 bytes (24..1100)
///   then per tick, until the input ends (at most kMaxCacheTicks ticks):
///     edits: a count byte (% 8), then 4 bytes per edit: op % 8, entity, a, b (edit_world)
///     per client, 2 bytes:
///       [0] bits 0..1: 0-1 acknowledge tick - delay, 2 none (lost), 3 acknowledge
///           tick - (bits 2..5) (late, early, repeated or never sent); bits 6..7: budget 0-1 as
///           set up, 2 a quarter of it, 3 1100
///       [1] viewer x = (bits 0..2) * 5 - 17 m, z = (bits 3..5) * 5 - 17 m; bits 6..7 both set:
///           this encode goes without the cache

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snapshot_decoder_world.h"

namespace ricochet::fuzz {

inline constexpr std::uint32_t kMaxCacheTicks = 64;
inline constexpr std::size_t kMaxCacheEntities = 300;

struct CacheSetup {
  proto::SnapshotCacheLayers layers;
  std::size_t max_streams = 1;
  std::size_t clients = 1;
  std::uint32_t ack_delay_ticks = 1;
  std::size_t budget_bytes = 1100;
};

struct ClientTick {
  bool ack = false;
  std::uint32_t ack_tick = 0;
  std::size_t budget_bytes = 1100;
  std::array<float, 3> viewer_m{};
  bool without_cache = false;
};

class CacheInput {
 public:
  CacheInput(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return at_ >= size_; }

  CacheSetup setup() {
    const std::uint8_t layers = next();
    const std::uint8_t slots = next();
    const std::uint16_t budget = static_cast<std::uint16_t>((next() << 8) | next());
    setup_.layers = {.streams = !(layers & 1),
                     .deltas = !(layers & 2),
                     .world_baselines = !(layers & 4),
                     .walks = !(layers & 8),
                     .whole_world_start = !(layers & 16)};
    setup_.clients = 1 + static_cast<std::size_t>(layers >> 5);
    setup_.max_streams = 1 + slots % 4;
    setup_.ack_delay_ticks = 1 + static_cast<std::uint32_t>((slots >> 2) % 6);
    setup_.budget_bytes = 24 + budget % 1077;
    return setup_;
  }

  /// Applies this tick's edits to `world`, which stays sorted by id, ids unique, every field in
  /// the spec's ranges.
  void edit_world(std::vector<proto::QuantizedEntity>& world, const proto::QuantizationSpec& spec) {
    const int edits = next() % 8;
    for (int e = 0; e < edits; ++e) {
      const std::uint8_t op = next() % 8;
      const std::uint8_t which = next();
      const std::uint8_t a = next();
      const std::uint8_t b = next();
      if (op == 5) {
        add(world, spec, a, b);
        continue;
      }
      if (world.empty()) continue;
      const std::size_t index = which % world.size();
      proto::QuantizedEntity& entity = world[index];
      switch (op) {
        case 0:  // a small move, along one axis
          move(entity, spec, a % 3, static_cast<std::int8_t>(b));
          break;
        case 1:  // a velocity change
          entity.velocity[a % 3] = clamp_velocity(
              static_cast<std::int64_t>(entity.velocity[a % 3]) + static_cast<std::int8_t>(b),
              spec);
          break;
        case 2:  // a turn
          entity.orientation_largest = static_cast<std::uint8_t>(a % 4);
          entity.orientation[a / 4 % 3] = std::clamp<std::int32_t>(
              static_cast<std::int8_t>(b) * 4, -spec.orientation_limit(), spec.orientation_limit());
          break;
        case 3:
          entity.flags ^= b;
          break;
        case 4:
          world.erase(world.begin() + static_cast<std::ptrdiff_t>(index));
          break;
        case 6:  // a teleport: anywhere, at the limit's velocity
          for (int axis = 0; axis < 3; ++axis) {
            entity.position[axis] = static_cast<std::uint32_t>(
                (a * 257u + b * 65537u * (axis + 1)) % spec.position_steps(axis));
            entity.velocity[axis] =
                (b >> axis) & 1 ? spec.velocity_limit() : -spec.velocity_limit();
          }
          break;
        case 7:  // a crowd moves: every entity from `which` on, one in (a % 4 + 1)
          for (std::size_t k = index; k < world.size(); k += a % 4 + 1) {
            move(world[k], spec, static_cast<int>(k % 3), static_cast<std::int8_t>(b));
          }
          break;
        default:
          break;
      }
    }
  }

  ClientTick client_tick(std::uint32_t tick) {
    const std::uint8_t c0 = next();
    const std::uint8_t c1 = next();
    ClientTick client;
    switch (c0 & 3) {
      case 0:
      case 1:
        client.ack = tick > setup_.ack_delay_ticks;
        client.ack_tick = tick - setup_.ack_delay_ticks;
        break;
      case 2:
        break;
      default:
        client.ack = true;
        client.ack_tick = tick - ((c0 >> 2) & 15);  // may wrap: a tick never sent
        break;
    }
    switch (c0 >> 6) {
      case 2:
        client.budget_bytes = std::max<std::size_t>(16, setup_.budget_bytes / 4);
        break;
      case 3:
        client.budget_bytes = 1100;
        break;
      default:
        client.budget_bytes = setup_.budget_bytes;
        break;
    }
    client.viewer_m = {static_cast<float>(c1 & 7) * 5 - 17, 1,
                       static_cast<float>((c1 >> 3) & 7) * 5 - 17};
    client.without_cache = (c1 & 0xC0) == 0xC0;
    return client;
  }

 private:
  std::uint8_t next() { return at_ < size_ ? data_[at_++] : (at_++, 0); }

  static std::int32_t clamp_velocity(std::int64_t value, const proto::QuantizationSpec& spec) {
    return static_cast<std::int32_t>(
        std::clamp<std::int64_t>(value, -spec.velocity_limit(), spec.velocity_limit()));
  }
  static void move(proto::QuantizedEntity& entity, const proto::QuantizationSpec& spec, int axis,
                   std::int8_t steps) {
    const std::int64_t moved = static_cast<std::int64_t>(entity.position[axis]) + steps * 16;
    entity.position[axis] = static_cast<std::uint32_t>(
        std::clamp<std::int64_t>(moved, 0, spec.position_steps(axis) - 1));
  }
  /// A new entity after the last id, so the world stays sorted.
  static void add(std::vector<proto::QuantizedEntity>& world, const proto::QuantizationSpec& spec,
                  std::uint8_t a, std::uint8_t b) {
    if (world.size() >= kMaxCacheEntities) return;
    proto::QuantizedEntity entity;
    entity.id = (world.empty() ? 0 : world.back().id) + 1 + a % 4;
    for (int axis = 0; axis < 3; ++axis) {
      entity.position[axis] = static_cast<std::uint32_t>((a * 131u + b * 8191u * (axis + 1)) %
                                                         spec.position_steps(axis));
      entity.velocity[axis] = clamp_velocity(static_cast<std::int8_t>(b) * (axis + 1), spec);
    }
    entity.flags = static_cast<std::uint8_t>(b & 0x81);
    world.push_back(entity);
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
  CacheSetup setup_;
};

}  // namespace ricochet::fuzz
