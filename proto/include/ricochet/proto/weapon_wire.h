#pragma once
/// Weapons on the wire (game.proto; PROTOCOL.md `Input`, `ServerPayload`; server/GAMEPLAY.md):
/// which Input.weapon_slot selects which Weapon, how PlayerStatus.ammo is indexed, and where a shot
/// leaves the player. The numbers each weapon flies by are the match's, in the join reply's
/// `weapons` (WeaponSpec).

#include <cstdint>
#include <optional>

#include "ricochet/wire/game.pb.h"

namespace ricochet::proto {

/// Input.weapon_slot lies in 0..kMaxWeaponSlot: 0 keeps the weapon, slot n selects Weapon n.
inline constexpr std::uint32_t kMaxWeaponSlot = 9;
/// Weapons 1..kWeaponCount exist (rifle, rocket launcher, grenade launcher): the last of
/// game.proto's Weapon enum.
inline constexpr std::uint32_t kWeaponCount = static_cast<std::uint32_t>(wire::Weapon_MAX);

/// The weapon `slot` selects; nothing for 0 (keep the weapon) or a slot without a weapon.
std::optional<wire::Weapon> weapon_of_slot(std::uint32_t slot);

/// The Input.weapon_slot that selects `weapon`.
constexpr std::uint32_t slot_of(wire::Weapon weapon) {
  return static_cast<std::uint32_t>(weapon);
}

/// The rounds PlayerStatus.ammo holds for `weapon` (index weapon - 1); 0 when it holds none.
std::int32_t ammo_of(const wire::PlayerStatus& status, wire::Weapon weapon);

/// Shots (rays, rockets, grenades) leave from this far above the player's centre, m.
inline constexpr float kShotHeightM = 0.25f;

}  // namespace ricochet::proto
