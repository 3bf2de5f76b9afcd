// The TOML map format: the shipped maps, every key, OBJ meshes, replays from the recorded files,
// and errors that name the file, the line, the item and what is wrong.

#include "ricochet/server/map.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server::map_test {
namespace {

using physics::Vec3;

// Lines 1..5; whatever follows starts at line 6 and must be a [[table]].
const std::string kHeader =
    "format = 1\nname = \"test\"\n[bounds]\nmin = [-10, -1, -10]\nmax = [10, 10, 10]\n";
const std::string kSpawn = "[[spawn]]\nposition = [0, 0.5, 0]\n";

std::string shipped(const char* name) {
  return (std::filesystem::path(RICOCHET_SOURCE_DIR "/server/maps") / name).string();
}

/// A reader over in-memory files, as a recording gives them.
MapFileReader reader(std::map<std::string, std::string> files) {
  return [files = std::move(files)](std::string_view path,
                                    std::string& error) -> std::optional<std::string> {
    if (const auto found = files.find(std::string(path)); found != files.end()) {
      return found->second;
    }
    error = "no such file";
    return std::nullopt;
  };
}

Map parsed(const std::string& text, const MapFileReader& read = {}) {
  MapResult result = parse_map(text, "t.toml", read);
  if (const MapError* error = std::get_if<MapError>(&result)) {
    ADD_FAILURE() << error->describe();
    return {};
  }
  return std::get<Map>(std::move(result));
}

MapError error_of(const std::string& text, const MapFileReader& read = {}) {
  MapResult result = parse_map(text, "t.toml", read);
  EXPECT_TRUE(std::holds_alternative<MapError>(result)) << "parsed:\n" << text;
  return std::holds_alternative<MapError>(result) ? std::get<MapError>(result) : MapError{};
}

Map loaded(const char* name) {
  MapResult result = load_map_file(shipped(name));
  if (const MapError* error = std::get_if<MapError>(&result)) {
    ADD_FAILURE() << error->describe();
    return {};
  }
  return std::get<Map>(std::move(result));
}

physics::World world_of(const Map& map) {
  physics::World world = physics::World::create(physics::profiles::arena_players()).value();
  EXPECT_TRUE(add_map_to_world(map, world).ok());
  return world;
}

std::size_t count_team(const Map& map, Team team) {
  std::size_t n = 0;
  for (const MapSpawn& spawn : map.spawns) n += spawn.team == team;
  return n;
}

std::size_t count_kind(const Map& map, PickupKind kind) {
  std::size_t n = 0;
  for (const MapPickup& pickup : map.pickups) n += pickup.kind == kind;
  return n;
}

TEST(Map, TheArenaLoadsAndBuildsAWorld) {
  const Map map = loaded("arena.toml");
  EXPECT_EQ(map.name, "arena");
  ASSERT_TRUE(map.floor_y_m);
  EXPECT_EQ(*map.floor_y_m, 0);
  EXPECT_EQ(map.bounds_min_m, Vec3(-22, -2, -22));
  EXPECT_EQ(map.bounds_max_m, Vec3(22, 12, 22));
  EXPECT_EQ(map.boxes.size(), 10u);  // 4 walls, 5 cover boxes, the platform
  ASSERT_EQ(map.meshes.size(), 1u);
  EXPECT_EQ(map.meshes[0].name, "ramp");
  EXPECT_EQ(map.meshes[0].indices.size(), 6u);
  EXPECT_EQ(map.spawns.size(), 16u);
  EXPECT_EQ(count_team(map, Team::Red), 7u);
  EXPECT_EQ(count_team(map, Team::Blue), 7u);
  EXPECT_EQ(map.pickups.size(), 4u);
  ASSERT_EQ(map.kill_volumes.size(), 1u);
  EXPECT_FALSE(map.kill_volumes[0].contains(Vec3(0, 0.45, 0)));
  EXPECT_TRUE(map.kill_volumes[0].contains(Vec3(0, -1.5, 0)));
  ASSERT_EQ(map.files.size(), 1u);
  EXPECT_EQ(map.files[0].path, shipped("arena.toml"));

  physics::World world = world_of(map);
  EXPECT_EQ(world.shape_count(), 12u);  // the floor, 10 boxes, the ramp
  // A ray down onto the ramp's middle hits it at half its height.
  physics::RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(8, 5, -6), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_NEAR(hit.point.y(), 1.0, 1e-4);
}

TEST(Map, TheFoundryHasTwoLevelsRampsThinWallsAPitAndALongSightLine) {
  const Map map = loaded("foundry.toml");
  EXPECT_EQ(map.name, "foundry");
  EXPECT_FALSE(map.floor_y_m);  // the ground is boxes around the pit
  EXPECT_GE(map.bounds_max_m.x() - map.bounds_min_m.x(), 80);
  EXPECT_GE(map.bounds_max_m.z() - map.bounds_min_m.z(), 80);
  EXPECT_GE(map.spawns.size(), 16u);
  EXPECT_GE(count_team(map, Team::Red), 8u);
  EXPECT_EQ(count_team(map, Team::Red), count_team(map, Team::Blue));
  EXPECT_GE(count_kind(map, PickupKind::Health), 1u);
  EXPECT_GE(count_kind(map, PickupKind::Armor), 1u);
  EXPECT_GE(count_kind(map, PickupKind::Ammo), 1u);
  ASSERT_EQ(map.kill_volumes.size(), 1u);
  EXPECT_EQ(map.kill_volumes[0].name, "pit");
  std::size_t thin = 0;
  for (const MapBox& box : map.boxes) thin += 2 * box.half_extents_m.z() <= 0.2f;
  EXPECT_GE(thin, 2u);
  ASSERT_EQ(map.meshes.size(), 1u);
  EXPECT_EQ(map.meshes[0].vertices_m.size(), 8u);
  EXPECT_EQ(map.meshes[0].indices.size(), 12u);  // a quad and two triangles per ramp
  ASSERT_EQ(map.files.size(), 2u);
  EXPECT_EQ(map.files[1].path, "foundry_ramps.obj");

  physics::World world = world_of(map);
  physics::RayHit hit;
  // The south aisle at eye height: 78 m with nothing in the way.
  EXPECT_FALSE(world.ray_cast_closest(Vec3(-39, 0.65f, -34), Vec3(1, 0, 0), 78, {}, hit));
  // The upper level: the bridge between the balconies, 78 m too.
  EXPECT_FALSE(world.ray_cast_closest(Vec3(-39, 6.65f, 0), Vec3(1, 0, 0), 78, {}, hit));
  // The ground, a balcony, and halfway up the west ramp.
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-20, 3, -30), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_NEAR(hit.point.y(), 0, 1e-4);
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-33, 10, 0), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_NEAR(hit.point.y(), 6, 1e-4);
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-20, 10, 27), Vec3(0, -1, 0), 20, {}, hit));
  EXPECT_NEAR(hit.point.y(), 3, 1e-4);
  // The pit is open down to the kill volume.
  EXPECT_FALSE(world.ray_cast_closest(Vec3(2, -0.1f, 2), Vec3(0, -1, 0), 11, {}, hit));
  EXPECT_TRUE(map.kill_volumes[0].contains(Vec3(2, -6, 2)));
}

TEST(Map, ParsesEveryKey) {
  const Map map = parsed(
      "format = 1\nname = \"every\"\nfloor_y = -0.5  # the ground\n"
      "[bounds]\nmin = [-10, -1, -10]\nmax = [10, 10, 10.5]\n"
      "[[box]]\ncenter = [1, 2, 3]\nhalf_extents = [0.5, 1, 1.5]\nyaw_deg = 90\n"
      "[[box]]\ncenter = [0, 0, 0]\nhalf_extents = [1, 1, 1]\n"
      "[[wall]]\nfrom = [0, 0]\nto = [0, 4]\nbase = 0\nheight = 3\nthickness = 0.2\n"
      "[[mesh]]\nname = \"ramp\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n"
      "triangles = [[0, 1, 2]]\n"
      "[[spawn]]\nposition = [1, 0.5, -1]\nyaw_deg = 180\nteam = \"red\"\n"
      "[[spawn]]\nposition = [-1, 0.5, 1]\nteam = \"blue\"\n"
      "[[spawn]]\nposition = [0, 0.5, 5]\n"
      "[[pickup]]\nkind = \"health\"\nposition = [2, 0.5, 2]\namount = 25\nrespawn_s = 20\n"
      "[[pickup]]\nkind = \"armor\"\nposition = [3, 0.5, 2]\namount = 200\nrespawn_s = 1\n"
      "[[pickup]]\nkind = \"ammo\"\nposition = [4, 0.5, 2]\namount = 100\nrespawn_s = 600.0\n"
      "[[kill_volume]]\nname = \"lava\"\nmin = [-10, -1, -10]\nmax = [10, -0.6, 10]\n");
  EXPECT_EQ(map.name, "every");
  EXPECT_EQ(map.bounds_min_m, Vec3(-10, -1, -10));
  EXPECT_EQ(map.bounds_max_m, Vec3(10, 10, 10.5));
  EXPECT_EQ(map.floor_y_m, -0.5f);
  ASSERT_EQ(map.boxes.size(), 3u);
  EXPECT_EQ(map.boxes[0].center_m, Vec3(1, 2, 3));
  EXPECT_EQ(map.boxes[0].half_extents_m, Vec3(0.5, 1, 1.5));
  EXPECT_NEAR(map.boxes[0].yaw_rad, 3.14159265 / 2, 1e-6);
  EXPECT_EQ(map.boxes[1].yaw_rad, 0);
  // The wall along +z from (0,0) to (0,4): 4 m long, 3 m high, 0.2 m thick, yaw -90°.
  EXPECT_TRUE(map.boxes[2].center_m.isApprox(Vec3(0, 1.5, 2)));
  EXPECT_TRUE(map.boxes[2].half_extents_m.isApprox(Vec3(2, 1.5, 0.1)));
  EXPECT_NEAR(map.boxes[2].yaw_rad, -3.14159265 / 2, 1e-6);
  ASSERT_EQ(map.meshes.size(), 1u);
  EXPECT_EQ(map.meshes[0].name, "ramp");
  EXPECT_EQ(map.meshes[0].vertices_m.size(), 3u);
  EXPECT_EQ(map.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(map.spawns.size(), 3u);
  EXPECT_EQ(map.spawns[0].position_m, Vec3(1, 0.5, -1));
  EXPECT_NEAR(map.spawns[0].yaw_rad, 3.14159265, 1e-6);
  EXPECT_EQ(map.spawns[0].team, Team::Red);
  EXPECT_EQ(map.spawns[1].team, Team::Blue);
  EXPECT_EQ(map.spawns[1].yaw_rad, 0);
  EXPECT_EQ(map.spawns[2].team, Team::None);
  ASSERT_EQ(map.pickups.size(), 3u);
  EXPECT_EQ(map.pickups[0].kind, PickupKind::Health);
  EXPECT_EQ(map.pickups[0].position_m, Vec3(2, 0.5, 2));
  EXPECT_EQ(map.pickups[0].amount, 25);
  EXPECT_EQ(map.pickups[0].respawn_s, 20);
  EXPECT_EQ(map.pickups[1].kind, PickupKind::Armor);
  EXPECT_EQ(map.pickups[2].kind, PickupKind::Ammo);
  EXPECT_EQ(map.pickups[2].respawn_s, 600);
  ASSERT_EQ(map.kill_volumes.size(), 1u);
  EXPECT_EQ(map.kill_volumes[0].name, "lava");
  EXPECT_EQ(map.kill_volumes[0].max_m, Vec3(10, -0.6, 10));
  ASSERT_EQ(map.files.size(), 1u);
  EXPECT_EQ(map.files[0].path, "t.toml");
}

TEST(Map, AWallIsABoxAlongItsLine) {
  const Map map = parsed(kHeader +
                         "[[wall]]\nfrom = [-2, 0]\nto = [2, 0]\nbase = 0\nheight = 2\n"
                         "thickness = 1\n" +
                         kSpawn);
  physics::World world = world_of(map);
  physics::RayHit hit;
  // The wall spans x -2..2 at z -0.5..0.5, y 0..2.
  ASSERT_TRUE(world.ray_cast_closest(Vec3(1.5, 1, 5), Vec3(0, 0, -1), 10, {}, hit));
  EXPECT_NEAR(hit.point.z(), 0.5, 1e-4);
  EXPECT_FALSE(world.ray_cast_closest(Vec3(2.5, 1, 5), Vec3(0, 0, -1), 10, {}, hit));
  EXPECT_FALSE(world.ray_cast_closest(Vec3(0, 2.5, 5), Vec3(0, 0, -1), 10, {}, hit));
}

struct BadMap {
  std::string text;
  int line;
  std::string item;
  std::string message_part;
};

const std::string kBox = "[[box]]\ncenter = [0, 0, 0]\n";                           // lines 6, 7
const std::string kWall = "[[wall]]\nfrom = [0, 0]\nto = [1, 1]\n";                 // lines 6..8
const std::string kMesh = "[[mesh]]\nname = \"m\"\n";                               // lines 6, 7
const std::string kTriangle = "vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n";     // line 8
const std::string kPickup = "[[pickup]]\nposition = [0, 0.5, 0]\nrespawn_s = 5\n";  // 6..8
const std::string kKill = "[[kill_volume]]\nname = \"k\"\nmin = [0, 0, 0]\n";       // 6..8

TEST(Map, EveryRuleIsRefusedNamingTheLineTheItemAndWhatCame) {
  const BadMap cases[] = {
      // The document and its top level.
      {"", 0, "format", "expected the format version (format = 1), missing"},
      {"format = 2\n", 1, "format", "expected an integer in 1..1, got 2"},
      {"format = \"1\"\n", 1, "format", "expected an integer, got string"},
      {"format = 1\nname = \"bad/name\"\n", 2, "name", "got 'bad/name'"},
      {"format = 1\nname = \"\"\n", 2, "name", "expected 1..32 of"},
      {"format = 1\nname = 7\n", 2, "name", "expected a string, got integer"},
      {"format = 1\nname = \"a\"\nname = \"b\"\n", 3, "toml", "malformed TOML"},
      {"format = 1\nname = \n", 2, "toml", "malformed TOML"},
      {"format = 1\nname = \"\xff\"\n", 2, "toml", "malformed TOML"},
      {"format = 1\ncolour = 3\n", 2, "colour", "unknown key (expected one of format, name"},
      // An empty key names itself "" (found by map_parser_fuzz: the item was empty).
      {"\"\" = \"\"\n", 1, "\"\"", "unknown key"},
      {kHeader + "[[box]]\n\"\" = 1\n", 7, "box 1 (\"\")", "unknown key"},
      {kHeader + "[[box]]\n\"\\u0001\" = 1\n", 7, "box 1 (?)", "unknown key"},
      {"format = 1\nname = \"a\"\n", 0, "bounds", "expected a table [bounds]"},
      {"format = 1\nname = \"a\"\nbounds = 3\n", 3, "bounds", "expected a table, got integer"},
      {kHeader + "[bounds.extra]\n", 6, "bounds (extra)", "unknown key (expected one of min, max)"},
      {kHeader + "[bounds]\n", 6, "toml", "malformed TOML"},
      // The bounds.
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [0, 0, 0]\nmax = [1, 0.5, 1]\n", 5,
       "bounds (max.y)", "expected at least min + 1 = 1, got 0.5"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [0, 0]\nmax = [1, 1, 1]\n", 4, "bounds (min)",
       "expected an array of 3 numbers [x, y, z], got an array of 2"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = 0\n", 4, "bounds (min)", "got integer"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [\"a\", 0, 0]\n", 4, "bounds (min.x)",
       "expected a number, got string"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [-inf, 0, 0]\n", 4, "bounds (min.x)",
       "expected a finite number, got -inf"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [0, nan, 0]\n", 4, "bounds (min.y)",
       "expected a finite number, got nan"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [0, 0, 1e300]\n", 4, "bounds (min.z)",
       "expected a number in -100000..100000, got 1e+300"},
      {"format = 1\nname = \"a\"\n[bounds]\nmin = [0, 0, 0]\n", 3, "bounds (max)", "missing"},
      {"format = 1\nname = \"a\"\nfloor_y = 20\n[bounds]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n", 3,
       "floor_y", "expected a number in 0..1, got 20"},
      // Boxes.
      {kHeader + kBox + "half_extents = [1, -1, 1]\n", 8, "box 1 (half_extents.y)",
       "expected a number >= 0.001, got -1"},
      {kHeader + kBox + "half_extents = [1, 1e-50, 1]\n", 8, "box 1 (half_extents.y)", "got 1e-50"},
      {kHeader + kBox, 6, "box 1 (half_extents)", "expected an array [x, y, z] (m), missing"},
      {kHeader + "[[box]]\ncenter = [50, 0, 0]\nhalf_extents = [1, 1, 1]\n", 7, "box 1 (center)",
       "expected a point inside the bounds (-10, -1, -10)..(10, 10, 10), got (50, 0, 0)"},
      {kHeader + kBox + "half_extents = [1, 1, 1]\nyaw_deg = 400\n", 9, "box 1 (yaw_deg)",
       "expected a number in -360..360, got 400"},
      {kHeader + kBox + "half_extents = [1, 1, 1]\ncolour = \"red\"\n", 9, "box 1 (colour)",
       "unknown key (expected one of center, half_extents, yaw_deg)"},
      {kHeader + kBox + "half_extents = [1, 1, 1]\n" + kBox + "half_extents = [1, 0, 1]\n", 11,
       "box 2 (half_extents.y)", "got 0"},
      {kHeader + "[box]\ncenter = [0, 0, 0]\n", 6, "box",
       "expected an array of tables ([[box]]), got table"},
      {"box = [1]\n" + kHeader, 1, "box 1", "expected a table, got integer"},
      // Walls.
      {kHeader + "[[wall]]\nfrom = [1, 1]\nto = [1, 1]\nbase = 0\nheight = 2\nthickness = 1\n", 8,
       "wall 1 (to)", "expected an end at least 0.002 m from the start, got 0 m"},
      {kHeader + kWall + "base = 0\nheight = 0\nthickness = 1\n", 10, "wall 1 (height)",
       "expected a number in 0.002..100000, got 0"},
      {kHeader + kWall + "base = 0\nheight = 1\n", 6, "wall 1 (thickness)",
       "expected a number, missing"},
      {kHeader + "[[wall]]\nfrom = [0, 0, 0]\n", 7, "wall 1 (from)",
       "expected an array of 2 numbers [x, z], got an array of 3"},
      {kHeader + kWall + "base = 50\nheight = 1\nthickness = 1\n", 6, "wall 1 (centre)",
       "inside the bounds"},
      // Meshes.
      {kHeader + kMesh + kTriangle + "triangles = [[0, 1, 5]]\n", 9, "mesh 1 (triangles 0)",
       "expected an integer in 0..2, got 5"},
      {kHeader + kMesh + kTriangle + "triangles = [[0, 1, -1]]\n", 9, "mesh 1 (triangles 0)",
       "got -1"},
      {kHeader + kMesh + kTriangle + "triangles = [[0, 1, 1]]\n", 9, "mesh 1 (triangles 0)",
       "degenerate"},
      {kHeader + kMesh + kTriangle + "triangles = [[0, 1]]\n", 9, "mesh 1 (triangles 0)",
       "expected three vertex numbers [a, b, c], got an array of 2"},
      {kHeader + kMesh + kTriangle + "triangles = []\n", 9, "mesh 1 (triangles)",
       "got 0 triangles"},
      {kHeader + kMesh + "vertices = []\n", 8, "mesh 1 (vertices)",
       "expected an array of 1..65536 points [x, y, z], got 0 points"},
      {kHeader + kMesh + "vertices = [[0, 0, 99]]\n", 8, "mesh 1 (vertices 0)",
       "inside the bounds"},
      {kHeader + kMesh, 6, "mesh 1 (vertices)", "missing"},
      {kHeader + "[[mesh]]\nvertices = []\n", 6, "mesh 1 (name)", "expected a string, missing"},
      {kHeader + kMesh + kTriangle + "triangles = [[0, 1, 2]]\n" + kMesh, 11, "mesh 2 (name)",
       "expected a name no other mesh has, got 'm' (also mesh 1)"},
      {kHeader + kMesh + kTriangle + "obj = \"m.obj\"\n", 6, "mesh 1",
       "expected either obj or vertices and triangles, got both"},
      {kHeader + kMesh + "obj = \"m.obj\"\n", 8, "mesh 1 (obj)",
       "cannot read 'm.obj': this parse has no file reader"},
      {kHeader + kMesh + "obj = \"../m.obj\"\n", 8, "mesh 1 (obj)", "expected a relative path"},
      {kHeader + kMesh + "obj = \"/abs/m.obj\"\n", 8, "mesh 1 (obj)", "expected a relative path"},
      {kHeader + kMesh + "obj = \"m.txt\"\n", 8, "mesh 1 (obj)", "expected a relative path"},
      // Spawns.
      {kHeader, 0, "spawn", "expected at least one [[spawn]], got none"},
      {kHeader + "[[spawn]]\nposition = [0, -5, 0]\n", 7, "spawn 1 (position)",
       "inside the bounds"},
      {kHeader + kSpawn + "team = \"green\"\n", 8, "spawn 1 (team)",
       "expected \"red\" or \"blue\" (no key: any player), got 'green'"},
      {kHeader + kSpawn + kSpawn + "team = \"red\"\n", 8, "spawn",
       "expected team spawns for both teams or for none, got 1 red and 0 blue"},
      {kHeader + kSpawn + "yaw = 3\n", 8, "spawn 1 (yaw)", "unknown key"},
      // Pickups.
      {kHeader + kPickup + "kind = \"mega\"\namount = 1\n" + kSpawn, 9, "pickup 1 (kind)",
       "expected \"health\", \"armor\" or \"ammo\", got 'mega'"},
      {kHeader + kPickup + "kind = \"health\"\namount = 0\n" + kSpawn, 10, "pickup 1 (amount)",
       "expected an integer in 1..200, got 0"},
      {kHeader + kPickup + "kind = \"ammo\"\namount = 150\n" + kSpawn, 10, "pickup 1 (amount)",
       "expected an integer in 1..100, got 150"},
      {kHeader + kPickup + "kind = \"armor\"\namount = 2.5\n" + kSpawn, 10, "pickup 1 (amount)",
       "expected an integer, got floating-point"},
      {kHeader +
           "[[pickup]]\nposition = [0, 0.5, 0]\nrespawn_s = 0.5\nkind = \"ammo\"\n"
           "amount = 1\n" +
           kSpawn,
       8, "pickup 1 (respawn_s)", "expected a number in 1..600, got 0.5"},
      {kHeader + "[[pickup]]\nposition = [0, 50, 0]\nkind = \"ammo\"\n" + kSpawn, 7,
       "pickup 1 (position)", "inside the bounds"},
      // Kill volumes.
      {kHeader + kKill + "max = [0.05, 1, 1]\n" + kSpawn, 9, "kill_volume 1 (max.x)",
       "expected at least min + 0.1 = 0.1, got 0.05"},
      {kHeader + kKill + "max = [1, 1, 1]\n" + kKill + "max = [1, 1, 1]\n" + kSpawn, 11,
       "kill_volume 2 (name)", "no other kill volume has, got 'k'"},
      {kHeader + kKill + "max = [1, 1, 99]\n" + kSpawn, 9, "kill_volume 1 (max)",
       "inside the bounds"},
      {kHeader + "[[kill_volume]]\nname = \"pit\"\nmin = [-1, 0, -1]\nmax = [1, 1, 1]\n" + kSpawn,
       10, "spawn 1",
       "expected a position outside every kill volume, got (0, 0.5, 0) inside 'pit'"},
  };
  for (const BadMap& bad : cases) {
    const MapError error = error_of(bad.text);
    EXPECT_EQ(error.file, "t.toml") << bad.text << "\n" << error.describe();
    EXPECT_EQ(error.line, bad.line) << bad.text << "\n" << error.describe();
    EXPECT_EQ(error.item, bad.item) << bad.text << "\n" << error.describe();
    EXPECT_NE(error.message.find(bad.message_part), std::string::npos) << bad.text << "\n"
                                                                       << error.describe();
  }
}

TEST(Map, DescribeSaysFileLineItemAndWhat) {
  const MapError error = error_of(kHeader + kBox + "half_extents = [1, -1, 1]\n");
  EXPECT_EQ(error.describe(),
            "t.toml:8: box 1 (half_extents.y): expected a number >= 0.001, got -1");
  EXPECT_EQ(error_of(kHeader).describe(),
            "t.toml: spawn: expected at least one [[spawn]], got none");
}

TEST(Map, RefusesOversizedTextAndTooManyEntries) {
  const MapError big = error_of(std::string(kMaxMapBytes + 1, '\n'));
  EXPECT_EQ(big.item, "map");
  EXPECT_NE(big.message.find("expected at most 1048576 bytes"), std::string::npos);

  const std::string box = "[[box]]\ncenter = [0, 0, 0]\nhalf_extents = [1, 1, 1]\n";
  std::string boxes = kHeader;
  for (int k = 0; k < 1025; ++k) boxes += box;
  const MapError too_many = error_of(boxes + kSpawn);
  EXPECT_EQ(too_many.item, "box");
  EXPECT_EQ(too_many.message, "expected at most 1024 boxes, got 1025");

  // Boxes and walls share one cap.
  std::string mixed = kHeader;
  for (int k = 0; k < 1000; ++k) mixed += box;
  for (int k = 0; k < 30; ++k) {
    mixed += "[[wall]]\nfrom = [0, 0]\nto = [1, 0]\nbase = 0\nheight = 1\nthickness = 1\n";
  }
  const MapError shared = error_of(mixed + kSpawn);
  EXPECT_EQ(shared.item, "wall 25");
  EXPECT_NE(shared.message.find("at most 1024 boxes and walls together"), std::string::npos);

  std::string spawns = kHeader;
  for (int k = 0; k < 65; ++k) spawns += kSpawn;
  EXPECT_EQ(error_of(spawns).message, "expected at most 64 spawns, got 65");
}

TEST(Map, AMissingFileIsAnError) {
  const MapResult result = load_map_file("/nonexistent/ricochet/none.toml");
  ASSERT_TRUE(std::holds_alternative<MapError>(result));
  const MapError& error = std::get<MapError>(result);
  EXPECT_EQ(error.file, "/nonexistent/ricochet/none.toml");
  EXPECT_EQ(error.item, "map");
  EXPECT_NE(error.message.find("expected a readable file"), std::string::npos);
}

// --- OBJ meshes --------------------------------------------------------------------------------

const std::string kObjMesh = kHeader + kMesh + "obj = \"parts/m.obj\"\n" + kSpawn;

TEST(MapObj, AQuadInEveryIndexFormIsTwoTriangles) {
  const std::string obj =
      "# a unit square at y = 1, then a triangle by negative indices\r\n"
      "o square\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1 1.0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 1 0\ns off\ng group\nusemtl steel\n"
      "f 1/1/1 2/2/1 3/3/1 4//1\n"
      "v 5 1 5\nf -1 -2/1 -3/2\n"
      "f 1/1 2/2 5/3\n";
  const Map map = parsed(kObjMesh, reader({{"parts/m.obj", obj}}));
  ASSERT_EQ(map.meshes.size(), 1u);
  EXPECT_EQ(map.meshes[0].name, "m");
  EXPECT_EQ(map.meshes[0].vertices_m.size(), 5u);
  EXPECT_EQ(map.meshes[0].vertices_m[3], Vec3(0, 1, 1));
  EXPECT_EQ(map.meshes[0].indices,
            (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 4, 3, 2, 0, 1, 4}));
  ASSERT_EQ(map.files.size(), 2u);
  EXPECT_EQ(map.files[1].path, "parts/m.obj");
  EXPECT_EQ(map.files[1].text, obj);

  physics::World world = world_of(map);
  physics::RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(0.5, 5, 0.5), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_NEAR(hit.point.y(), 1, 1e-5);
}

TEST(MapObj, OneFileNamedTwiceIsReadOnce) {
  int reads = 0;
  const MapFileReader counting = [&reads](std::string_view, std::string&) {
    ++reads;
    return std::optional<std::string>("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n");
  };
  const Map map = parsed(kHeader + "[[mesh]]\nname = \"a\"\nobj = \"m.obj\"\n" +
                             "[[mesh]]\nname = \"b\"\nobj = \"m.obj\"\n" + kSpawn,
                         counting);
  EXPECT_EQ(reads, 1);
  EXPECT_EQ(map.meshes.size(), 2u);
  EXPECT_EQ(map.files.size(), 2u);
}

std::string many_corners(int corners) {
  std::string face = "v 0 0 0\nv 1 0 0\nv 0 0 1\nf";
  for (int k = 0; k < corners; ++k) face += " 1";
  return face + "\n";
}

struct BadObj {
  std::string obj;
  int line;
  std::string message_part;
};

TEST(MapObj, BadFilesAreRefusedNamingTheFileAndLine) {
  const BadObj cases[] = {
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 4\n", 4,
       "expected a vertex index 1..3 or -1..-3, got '4'"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 0\n", 4, "got '0'"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 -4\n", 4, "got '-4'"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 x\n", 4, "got 'x'"},
      {"f 1 2 3\n", 1, "expected a vertex index, but none is defined yet, got '1'"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1/1 2 3\n", 4,
       "expected a texture coordinate (vt) index, but none is defined yet"},
      {"v 0 0 0\nv 1 0 0\nv 0 0 1\nvn 0 1 0\nf 1//2 2//1 3//1\n", 5,
       "expected a normal (vn) index 1..1 or -1..-1, got '2'"},
      {"v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "expected a face of at least 3 corners, got 2"},
      {"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", 4, "degenerate triangle (corners 1, 2, 3)"},
      {"v 0 0\n", 1, "expected 'v X Y Z [W]', got 2 values"},
      {"v 0 nan 0\n", 1, "vertex 1: expected a decimal number within +-100000, got 'nan'"},
      {"v 0 1e9 0\n", 1, "got '1e9'"},
      {"v 0 0 0\nl 1 2\n", 2, "expected one of v, vt, vn, vp, f, o, g, s, usemtl, mtllib, got 'l'"},
      {"v 0 0 0\n", 0, "expected at least one face ('f' line), got none"},
      {many_corners(65), 4, "expected at most 64 values after the keyword"},
  };
  for (const BadObj& bad : cases) {
    const MapError error = error_of(kObjMesh, reader({{"parts/m.obj", bad.obj}}));
    EXPECT_EQ(error.file, "parts/m.obj") << bad.obj << "\n" << error.describe();
    EXPECT_EQ(error.line, bad.line) << bad.obj << "\n" << error.describe();
    EXPECT_EQ(error.item, "mesh 1 'm'") << bad.obj << "\n" << error.describe();
    EXPECT_NE(error.message.find(bad.message_part), std::string::npos) << bad.obj << "\n"
                                                                       << error.describe();
  }
}

TEST(MapObj, VerticesOutsideTheBoundsAndUnreadableFilesAreRefused) {
  const MapError outside =
      error_of(kObjMesh, reader({{"parts/m.obj", "v 0 0 0\nv 1 0 0\nv 0 0 50\nf 1 2 3\n"}}));
  EXPECT_EQ(outside.line, 8);
  EXPECT_EQ(outside.item, "mesh 1 (obj)");
  EXPECT_NE(outside.message.find("got vertex 3 at (0, 0, 50)"), std::string::npos);

  const MapError unreadable = error_of(kObjMesh, reader({}));
  EXPECT_EQ(unreadable.describe(),
            "t.toml:8: mesh 1 (obj): cannot read 'parts/m.obj': no such file");

  const MapError big =
      error_of(kObjMesh, reader({{"parts/m.obj", std::string(kMaxObjBytes + 1, '#')}}));
  EXPECT_EQ(big.line, 0);
  EXPECT_NE(big.message.find("expected at most 2097152 bytes"), std::string::npos);
}

// --- Replays from the recorded files -----------------------------------------------------------

void expect_same(const Map& a, const Map& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.bounds_min_m, b.bounds_min_m);
  EXPECT_EQ(a.bounds_max_m, b.bounds_max_m);
  EXPECT_EQ(a.floor_y_m, b.floor_y_m);
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  for (std::size_t k = 0; k < a.boxes.size(); ++k) {
    EXPECT_EQ(a.boxes[k].center_m, b.boxes[k].center_m);
    EXPECT_EQ(a.boxes[k].half_extents_m, b.boxes[k].half_extents_m);
    EXPECT_EQ(a.boxes[k].yaw_rad, b.boxes[k].yaw_rad);
  }
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t k = 0; k < a.meshes.size(); ++k) {
    EXPECT_EQ(a.meshes[k].name, b.meshes[k].name);
    EXPECT_EQ(a.meshes[k].vertices_m, b.meshes[k].vertices_m);
    EXPECT_EQ(a.meshes[k].indices, b.meshes[k].indices);
  }
  ASSERT_EQ(a.spawns.size(), b.spawns.size());
  for (std::size_t k = 0; k < a.spawns.size(); ++k) {
    EXPECT_EQ(a.spawns[k].position_m, b.spawns[k].position_m);
    EXPECT_EQ(a.spawns[k].yaw_rad, b.spawns[k].yaw_rad);
    EXPECT_EQ(a.spawns[k].team, b.spawns[k].team);
  }
  ASSERT_EQ(a.pickups.size(), b.pickups.size());
  for (std::size_t k = 0; k < a.pickups.size(); ++k) {
    EXPECT_EQ(a.pickups[k].kind, b.pickups[k].kind);
    EXPECT_EQ(a.pickups[k].position_m, b.pickups[k].position_m);
    EXPECT_EQ(a.pickups[k].amount, b.pickups[k].amount);
    EXPECT_EQ(a.pickups[k].respawn_s, b.pickups[k].respawn_s);
  }
  ASSERT_EQ(a.kill_volumes.size(), b.kill_volumes.size());
  for (std::size_t k = 0; k < a.kill_volumes.size(); ++k) {
    EXPECT_EQ(a.kill_volumes[k].name, b.kill_volumes[k].name);
    EXPECT_EQ(a.kill_volumes[k].min_m, b.kill_volumes[k].min_m);
    EXPECT_EQ(a.kill_volumes[k].max_m, b.kill_volumes[k].max_m);
  }
  ASSERT_EQ(a.files.size(), b.files.size());
  for (std::size_t k = 0; k < a.files.size(); ++k) {
    EXPECT_EQ(a.files[k].path, b.files[k].path);
    EXPECT_EQ(a.files[k].text, b.files[k].text);
  }
}

TEST(MapFiles, TheRecordedFilesGiveTheSameMap) {
  for (const char* name : {"arena.toml", "foundry.toml"}) {
    SCOPED_TRACE(name);
    const Map map = loaded(name);
    MapResult again = parse_map_files(map.files);
    ASSERT_TRUE(std::holds_alternative<Map>(again)) << std::get<MapError>(again).describe();
    expect_same(map, std::get<Map>(again));
  }
}

TEST(MapFiles, MissingOrExtraFilesAreRefused) {
  const Map foundry = loaded("foundry.toml");
  const std::vector<MapFile> alone = {foundry.files[0]};
  const MapResult missing = parse_map_files(alone);
  ASSERT_TRUE(std::holds_alternative<MapError>(missing));
  EXPECT_NE(std::get<MapError>(missing).message.find("not among the 0 files given"),
            std::string::npos);

  std::vector<MapFile> extra = foundry.files;
  extra.push_back(MapFile{"other.obj", "v 0 0 0\n"});
  const MapResult more = parse_map_files(extra);
  ASSERT_TRUE(std::holds_alternative<MapError>(more));
  EXPECT_EQ(std::get<MapError>(more).message,
            "expected the map and the 1 files it names, got 2 files");

  EXPECT_TRUE(std::holds_alternative<MapError>(parse_map_files({})));
}

}  // namespace
}  // namespace ricochet::server::map_test
