#pragma once
/// What a JoinMatchReply's CollisionWorld (world.proto) may hold: a client refuses a world
/// beyond these, and does not predict (PROTOCOL.md The collision world).

#include <cstddef>

namespace ricochet::proto {

struct CollisionWorldLimits {
  static constexpr int kMaxPlanes = 16;
  static constexpr int kMaxBoxes = 1024;
  static constexpr int kMaxMeshes = 64;
  static constexpr std::size_t kMaxVertices = 65536;   ///< over every mesh
  static constexpr std::size_t kMaxTriangles = 65536;  ///< over every mesh
  static constexpr float kMaxCoordinateM = 100000;     ///< |x|, |y|, |z| of any point, m
  static constexpr float kMaxGravityMps2 = 100;        ///< |g|, m/s²
};

}  // namespace ricochet::proto
