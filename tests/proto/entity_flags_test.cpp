// The game's bits of a snapshot entity's flags: the kind in bits 2..3 beside the state bits.

#include "ricochet/proto/entity_flags.h"

#include <gtest/gtest.h>

namespace ricochet::proto::entity_flags_test {
namespace {

TEST(EntityFlags, TheKindRoundTripsBesideTheStateBits) {
  const std::uint8_t state_bits =
      kEntityGrounded | kEntityDisconnected | kEntityDead | kEntityProtected;
  EXPECT_EQ(state_bits & kEntityKindMask, 0);
  for (const EntityKind kind : {EntityKind::Player, EntityKind::Rocket, EntityKind::Grenade}) {
    const auto flags = static_cast<std::uint8_t>(kind_flags(kind) | state_bits);
    EXPECT_EQ(entity_kind(flags), kind);
    EXPECT_EQ(flags & ~kEntityKindMask, state_bits);
  }
}

TEST(EntityFlags, KindsAreNumberedAsPublished) {
  EXPECT_EQ(kind_flags(EntityKind::Player), 0);
  EXPECT_EQ(kind_flags(EntityKind::Rocket), 1u << 2);
  EXPECT_EQ(kind_flags(EntityKind::Grenade), 2u << 2);
  EXPECT_EQ(entity_kind(0), EntityKind::Player);
  EXPECT_EQ(entity_kind(kEntityDead), EntityKind::Player);
}

TEST(EntityFlags, TheUnassignedKindIsNone) {
  EXPECT_EQ(entity_kind(kEntityKindMask), std::nullopt);
  EXPECT_EQ(entity_kind(kEntityKindMask | kEntityGrounded), std::nullopt);
}

}  // namespace
}  // namespace ricochet::proto::entity_flags_test
