#pragma once
/// Static geometry definitions: infinite planes, oriented boxes and triangle meshes.

#include <cstdint>
#include <vector>

#include "ricochet/physics/body.h"

namespace ricochet::physics {

/// The half-space below the plane n·x = offset is solid; the normal points out of the solid.
struct PlaneDef {
  Vec3 normal = Vec3::UnitY();  ///< normalised on creation, must be non-zero
  Real offset = 0;              ///< m along the normalised normal (not rescaled)
  Material material{};
  Filter filter{};
};

/// Solid oriented box.
struct BoxDef {
  Vec3 center = Vec3::Zero();  ///< m
  Quat orientation = Quat::Identity();
  Vec3 half_extents = Vec3::Ones();  ///< m, each > 0
  Material material{};
  Filter filter{};
};

/// Two-sided triangle soup, stored in a bounding volume hierarchy.
struct MeshDef {
  std::vector<Vec3> vertices;          ///< m
  std::vector<std::uint32_t> indices;  ///< three per triangle, each < vertices.size()
  Material material{};
  Filter filter{};
};

enum class ShapeType : std::uint8_t { Plane, Box, Mesh };

}  // namespace ricochet::physics
