#pragma once
/// The collision world of a join reply (world.proto, PROTOCOL.md The collision world) as a
/// physics world a client predicts its player in. The reply is untrusted: every count, length,
/// number and range is checked first, and the first problem is returned as a message naming the
/// item and what was expected; nothing NaN, infinite or absurd reaches physics. Depends on the
/// physics core and proto's messages only (it has a libFuzzer target, tests/fuzz).

#include <cstddef>
#include <string>
#include <variant>

#include "ricochet/physics/body.h"
#include "ricochet/physics/character_motion.h"
#include "ricochet/physics/world.h"
#include "ricochet/proto/collision_world_limits.h"
#include "ricochet/wire/world.pb.h"

namespace ricochet::bot {

/// A world to predict in: the static geometry, the players' body and the movement rules.
struct PredictionWorld {
  physics::World world;
  physics::BodyDef player;  ///< character_body_def() with the reply's radius and mass
  physics::CharacterMotionConfig motion;
};

/// Checks `in` and builds its world (profiles::arena_players() with restitution on, as the
/// match's, and the reply's gravity). The error says what is wrong: "box 3 half_extents_m.y
/// must be 0.001..100000, got -1".
std::variant<PredictionWorld, std::string> build_prediction_world(const wire::CollisionWorld& in);

}  // namespace ricochet::bot
