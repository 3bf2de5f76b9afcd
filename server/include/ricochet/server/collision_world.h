#pragma once
/// The collision world a JoinMatchReply carries (world.proto, PROTOCOL.md The collision world):
/// a map's static geometry as add_map_to_world() puts it into the match's physics world, the
/// players' body and gravity, and the match's movement rules, so that a client predicts its
/// player with the same numbers as the server.

#include <cstddef>
#include <memory>

#include "ricochet/server/map.h"
#include "ricochet/server/movement.h"
#include "ricochet/wire/world.pb.h"

namespace ricochet::server {

/// A serialised world larger than this is not sent (the join reply must fit the control
/// channel's 64 KiB frame with the token and keys); clients then cannot predict.
inline constexpr std::size_t kMaxCollisionWorldBytes = 56 * 1024;

/// The world of `map` moved by `movement`; nullptr when it is over kMaxCollisionWorldBytes (the
/// caller says so: the match's clients cannot predict).
std::shared_ptr<const wire::CollisionWorld> collision_world(const Map& map,
                                                            const MovementConfig& movement);

}  // namespace ricochet::server
