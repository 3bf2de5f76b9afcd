/// Weapons on the wire (weapon_wire.h).

#include "ricochet/proto/weapon_wire.h"

namespace ricochet::proto {

std::optional<wire::Weapon> weapon_of_slot(std::uint32_t slot) {
  if (slot < 1 || slot > kWeaponCount) return std::nullopt;
  return static_cast<wire::Weapon>(slot);
}

std::int32_t ammo_of(const wire::PlayerStatus& status, wire::Weapon weapon) {
  const int index = static_cast<int>(weapon) - 1;
  return index >= 0 && index < status.ammo_size() ? status.ammo(index) : 0;
}

}  // namespace ricochet::proto
