#pragma once
/// Arena maps: a TOML file (server/maps/FORMAT.md documents every key, with an example), its
/// validating parser, Wavefront OBJ meshes the map names, and the static geometry a map adds to
/// a physics world. A map holds the bounds (which also fix the snapshot quantisation range), an
/// optional floor plane, boxes and walls, triangle meshes (inline or from an OBJ file), spawn
/// points (any player or one team's), pickups and kill volumes.
///
/// Loading validates everything; the first error stops it and names the file, the line, the
/// item and what was expected and what came. A map that fails never half-loads: the result is a
/// Map or a MapError, nothing in between.

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"

namespace ricochet::server {

/// The same numbers as wire::Team.
enum class Team : std::uint8_t { None = 0, Red = 1, Blue = 2 };

/// The same numbers as wire::PickupKind.
enum class PickupKind : std::uint8_t { Health = 1, Armor = 2, Ammo = 3 };

struct MapBox {
  physics::Vec3 center_m = physics::Vec3::Zero();
  physics::Vec3 half_extents_m = physics::Vec3::Ones();  ///< each >= 0.001 m
  float yaw_rad = 0;                                     ///< about +Y
};

struct MapMesh {
  std::string name;
  std::vector<physics::Vec3> vertices_m;
  std::vector<std::uint32_t> indices;  ///< three per triangle
};

struct MapSpawn {
  physics::Vec3 position_m = physics::Vec3::Zero();  ///< centre of the player's sphere
  float yaw_rad = 0;
  /// Team::None: any player (free-for-all, and team deathmatch when the map has no team spawns).
  Team team = Team::None;
};

/// Taken by touching: a player whose centre comes within 1.0 m of the pickup's position.
struct MapPickup {
  PickupKind kind = PickupKind::Health;
  physics::Vec3 position_m = physics::Vec3::Zero();
  /// Health and Armor: hit points, 1..200. Ammo: boxes, 1..100 (each gives every weapon its
  /// WeaponConfig::ammo_per_pickup rounds).
  int amount = 0;
  float respawn_s = 0;  ///< s until it is back after being taken, 1..600
};

/// A player whose centre enters the box dies (a pit below the level, lava).
struct MapKillVolume {
  std::string name;
  physics::Vec3 min_m = physics::Vec3::Zero();
  physics::Vec3 max_m = physics::Vec3::Zero();

  bool contains(const physics::Vec3& point_m) const;
};

/// A file a map was loaded from: its path and its bytes.
struct MapFile {
  std::string path;  ///< the map: as given to the loader; an OBJ: as the map names it
  std::string text;
};

struct Map {
  std::string name;
  physics::Vec3 bounds_min_m = physics::Vec3::Zero();
  physics::Vec3 bounds_max_m = physics::Vec3::Zero();
  std::optional<float> floor_y_m;  ///< the plane y = floor_y_m, solid below
  std::vector<MapBox> boxes;       ///< boxes and walls
  std::vector<MapMesh> meshes;
  std::vector<MapSpawn> spawns;
  std::vector<MapPickup> pickups;
  std::vector<MapKillVolume> kill_volumes;
  /// Every file read, the map first, then each OBJ file once in the order first named.
  /// parse_map_files(files) gives this map again (replays carry them).
  std::vector<MapFile> files;

  /// Inside the bounds (borders included).
  bool contains(const physics::Vec3& point_m) const;
};

/// What is wrong with a map: where and what.
struct MapError {
  std::string file;     ///< the map's or the OBJ's path
  std::string item;     ///< e.g. "box 3 (half_extents.y)": the 1-based entry and its key
  std::string message;  ///< what was expected and what came
  int line = 0;         ///< 1-based; 0 when the error is about the whole file

  /// "maps/x.toml:12: box 3 (half_extents.y): expected a number >= 0.001, got -1"
  std::string describe() const;
};

using MapResult = std::variant<Map, MapError>;

/// Reads a file the map names (an `obj = "..."` mesh). `path` is as the map writes it (relative
/// to the map's directory); on failure returns nullopt with `error` saying why.
using MapFileReader =
    std::function<std::optional<std::string>(std::string_view path, std::string& error)>;

inline constexpr std::size_t kMaxMapBytes = 1u << 20;  ///< a map's TOML text
inline constexpr std::size_t kMaxObjBytes = 2u << 20;  ///< each OBJ file

/// Parses and validates a map's TOML text; `file` names it in errors and in Map::files. Without
/// a reader an OBJ reference is an error. Never throws, never asserts on bad input.
MapResult parse_map(std::string_view text, std::string_view file = "<map>",
                    const MapFileReader& read = {});

/// Reads the map at `path` and the OBJ files it names (relative to its directory), each within
/// its size cap, and parses them.
MapResult load_map_file(const std::string& path);

/// Parses a map from the files it was loaded from (Map::files): files[0] is the map, the rest
/// are what it names, by path. Gives the same Map as load_map_file did.
MapResult parse_map_files(std::span<const MapFile> files);

/// Reads a Wavefront OBJ text into a mesh: `v X Y Z [W]` vertices, `f` faces of 3..64 corners in
/// the v, v/vt, v/vt/vn and v//vn forms with 1-based or negative (relative) indices, fanned into
/// triangles; vt and vn only count (face indices into them are checked); vp, o, g, s, usemtl,
/// mtllib and comments are ignored. Errors name `file` and the line; `item` names the mesh.
/// Vertices are not checked against any bounds here.
std::variant<MapMesh, MapError> parse_obj(std::string_view text, std::string_view file,
                                          std::string_view item);

/// Adds the map's floor, boxes and meshes as static shapes (layer kLayerStatic).
physics::Status add_map_to_world(const Map& map, physics::World& world);

}  // namespace ricochet::server
