#pragma once
/// Arena maps: a small text format, its validating parser, and the static geometry it adds to a
/// physics world. The format (server/maps/FORMAT.md has it with an example):
///
///   # a comment runs to the end of the line; blank lines are ignored
///   ricochet-map 1                          first statement: the format version
///   name arena                              1..32 of A-Z a-z 0-9 _ -
///   bounds MINX MINY MINZ MAXX MAXY MAXZ     m, once, before any geometry; each max > min
///   floor Y                                  m, optional, once: the plane y = Y, solid below
///   box CX CY CZ HX HY HZ [YAW]              centre (m, inside bounds), half extents (m, >= 0.001),
///                                            yaw about +Y (degrees, default 0)
///   wall X0 Z0 X1 Z1 BASE HEIGHT THICKNESS   a vertical slab along (X0,Z0)-(X1,Z1) from y=BASE
///   mesh NAME                                a triangle mesh (e.g. a ramp) until `end`:
///     vertex X Y Z                           m, inside bounds, numbered from 0 per mesh
///     triangle A B C                         three distinct vertex numbers, non-zero area
///   end
///   spawn X Y Z YAW                          centre of a player's sphere (m, inside bounds), yaw
///                                            in degrees; 1..64 of them
///
/// Tokens are separated by spaces or tabs; numbers are decimal (1, -2.5, 3e-2), finite, within
/// ±100000. Limits: 1 MiB of text, 512 characters a line, 1024 boxes and walls, 64 meshes of at
/// most 65536 vertices and 65536 triangles each. The first error stops the parse and names the
/// line, the field, what was expected and what came.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"

namespace ricochet::server {

struct MapBox {
  physics::Vec3 center_m = physics::Vec3::Zero();
  physics::Vec3 half_extents_m = physics::Vec3::Ones();
  float yaw_rad = 0;  ///< about +Y
};

struct MapMesh {
  std::string name;
  std::vector<physics::Vec3> vertices_m;
  std::vector<std::uint32_t> indices;  ///< three per triangle
};

struct MapSpawn {
  physics::Vec3 position_m = physics::Vec3::Zero();  ///< centre of the player's sphere
  float yaw_rad = 0;
};

struct Map {
  std::string name;
  physics::Vec3 bounds_min_m = physics::Vec3::Zero();
  physics::Vec3 bounds_max_m = physics::Vec3::Zero();
  std::optional<float> floor_y_m;
  std::vector<MapBox> boxes;  ///< boxes and walls
  std::vector<MapMesh> meshes;
  std::vector<MapSpawn> spawns;

  bool contains(const physics::Vec3& point_m) const;
};

/// What is wrong with a map text: where and what.
struct MapError {
  int line = 0;         ///< 1-based; 0 when the error is about the whole text or file
  std::string field;    ///< e.g. "box half_extents.y"
  std::string message;  ///< what was expected and what came

  /// "line 12: box half_extents.y: expected a number > 0, got '-1'"
  std::string describe() const;
};

using MapResult = std::variant<Map, MapError>;

inline constexpr std::size_t kMaxMapBytes = 1u << 20;

/// Parses and validates a map text; never throws, never asserts on bad input.
MapResult parse_map(std::string_view text);

/// Reads the file at `path` (at most kMaxMapBytes) and parses it.
MapResult load_map_file(const std::string& path);

/// Adds the map's floor, boxes and meshes as static shapes (layer kLayerStatic).
physics::Status add_map_to_world(const Map& map, physics::World& world);

}  // namespace ricochet::server
