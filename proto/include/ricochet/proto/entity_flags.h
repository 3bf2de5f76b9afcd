#pragma once
/// The game's bits of a snapshot entity's `flags` (EntityState.flags, 8 bits; PROTOCOL.md
/// Entities in snapshots). The snapshot codec carries them opaquely; the match sets them and a
/// client reads them with these names.
///
///   bit 0     grounded       bit 4  dead
///   bit 1     disconnected   bit 5  protected
///   bits 2..3 kind (EntityKind)

#include <cstddef>
#include <cstdint>
#include <optional>

namespace ricochet::proto {

enum EntityFlag : std::uint8_t {
  kEntityGrounded = 1u << 0,      ///< a player standing on something (it can jump)
  kEntityDisconnected = 1u << 1,  ///< its player is away, within the reconnect grace
  kEntityDead = 1u << 4,          ///< a player waiting to respawn (not hittable, not moving)
  kEntityProtected = 1u << 5,     ///< a player under spawn protection
};

/// What an entity is, in bits 2..3 of its flags. The value 3 is unassigned.
enum class EntityKind : std::uint8_t { Player = 0, Rocket = 1, Grenade = 2 };
inline constexpr std::size_t kEntityKindCount = static_cast<std::size_t>(EntityKind::Grenade) + 1;
inline constexpr unsigned kEntityKindShift = 2;
inline constexpr std::uint8_t kEntityKindMask = 3u << kEntityKindShift;

/// The kind bits of `kind`, to or into a flags byte.
constexpr std::uint8_t kind_flags(EntityKind kind) {
  return static_cast<std::uint8_t>(static_cast<unsigned>(kind) << kEntityKindShift);
}

/// The kind a flags byte names; nothing for the unassigned value 3.
constexpr std::optional<EntityKind> entity_kind(std::uint8_t flags) {
  const unsigned value = (flags & kEntityKindMask) >> kEntityKindShift;
  if (value >= kEntityKindCount) return std::nullopt;
  return static_cast<EntityKind>(value);
}

}  // namespace ricochet::proto
