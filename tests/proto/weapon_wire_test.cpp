// Weapons on the wire: slots select weapons, PlayerStatus.ammo is indexed by weapon - 1.

#include "ricochet/proto/weapon_wire.h"

#include <gtest/gtest.h>

namespace ricochet::proto::weapon_wire_test {
namespace {

TEST(WeaponWire, SlotNSelectsWeaponN) {
  EXPECT_EQ(weapon_of_slot(0), std::nullopt);  // keep the weapon
  EXPECT_EQ(weapon_of_slot(1), wire::WEAPON_RIFLE);
  EXPECT_EQ(weapon_of_slot(2), wire::WEAPON_ROCKET_LAUNCHER);
  EXPECT_EQ(weapon_of_slot(3), wire::WEAPON_GRENADE_LAUNCHER);
  EXPECT_EQ(weapon_of_slot(4), std::nullopt);
  EXPECT_EQ(weapon_of_slot(kMaxWeaponSlot), std::nullopt);
  for (std::uint32_t slot = 1; slot <= kWeaponCount; ++slot) {
    EXPECT_EQ(slot_of(*weapon_of_slot(slot)), slot);
  }
  EXPECT_EQ(kWeaponCount, static_cast<std::uint32_t>(wire::Weapon_MAX));
}

TEST(WeaponWire, AmmoIsIndexedByWeaponMinusOne) {
  wire::PlayerStatus status;
  for (const int rounds : {100, 10, 7}) status.add_ammo(rounds);
  EXPECT_EQ(ammo_of(status, wire::WEAPON_RIFLE), 100);
  EXPECT_EQ(ammo_of(status, wire::WEAPON_ROCKET_LAUNCHER), 10);
  EXPECT_EQ(ammo_of(status, wire::WEAPON_GRENADE_LAUNCHER), 7);
  EXPECT_EQ(ammo_of(status, wire::WEAPON_UNSPECIFIED), 0);
  status.mutable_ammo()->RemoveLast();
  EXPECT_EQ(ammo_of(status, wire::WEAPON_GRENADE_LAUNCHER), 0);  // a short list: none
}

}  // namespace
}  // namespace ricochet::proto::weapon_wire_test
