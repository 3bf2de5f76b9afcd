// The map text format: the sample map, every statement, and errors that name line and field.

#include "ricochet/server/map.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server {
namespace {

using physics::Vec3;

const std::string kHeader = "ricochet-map 1\nname test\nbounds -10 -1 -10 10 10 10\n";
const std::string kSpawn = "spawn 0 0.5 0 0\n";

std::string sample_map_path() {
  return (std::filesystem::path(__FILE__).parent_path() / "../../server/maps/arena.map").string();
}

Map parsed(const std::string& text) {
  MapResult result = parse_map(text);
  if (const MapError* error = std::get_if<MapError>(&result)) {
    ADD_FAILURE() << error->describe();
    return {};
  }
  return std::get<Map>(std::move(result));
}

MapError error_of(const std::string& text) {
  MapResult result = parse_map(text);
  EXPECT_TRUE(std::holds_alternative<MapError>(result)) << "parsed:\n" << text;
  return std::holds_alternative<MapError>(result) ? std::get<MapError>(result) : MapError{};
}

TEST(Map, TheSampleArenaLoads) {
  MapResult result = load_map_file(sample_map_path());
  ASSERT_TRUE(std::holds_alternative<Map>(result)) << std::get<MapError>(result).describe();
  const Map& map = std::get<Map>(result);
  EXPECT_EQ(map.name, "arena");
  ASSERT_TRUE(map.floor_y_m);
  EXPECT_EQ(*map.floor_y_m, 0);
  EXPECT_EQ(map.boxes.size(), 10u);  // 4 walls, 5 cover boxes, the platform
  ASSERT_EQ(map.meshes.size(), 1u);
  EXPECT_EQ(map.meshes[0].name, "ramp");
  EXPECT_EQ(map.meshes[0].indices.size(), 6u);
  EXPECT_EQ(map.spawns.size(), 16u);

  physics::World world = physics::World::create(physics::profiles::arena_players()).value();
  ASSERT_TRUE(add_map_to_world(map, world).ok());
  EXPECT_EQ(world.shape_count(), 12u);  // the floor, 10 boxes, the ramp
  // A ray down onto the ramp's middle hits it at half its height.
  physics::RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(8, 5, -6), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_NEAR(hit.point.y(), 1.0, 1e-4);
}

TEST(Map, ParsesEveryStatement) {
  const Map map = parsed(kHeader +
                         "floor -0.5   # the ground\n"
                         "\n"
                         "box 1 2 3  0.5 1 1.5  90\n"
                         "box 0 0 0  1 1 1\n"
                         "wall 0 0 0 4  0 3 0.2\n"
                         "mesh ramp\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n"
                         "  triangle 0 1 2\nend\n"
                         "spawn 1 0.5 -1 180\n");
  EXPECT_EQ(map.bounds_min_m, Vec3(-10, -1, -10));
  EXPECT_EQ(map.bounds_max_m, Vec3(10, 10, 10));
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
  EXPECT_EQ(map.meshes[0].vertices_m.size(), 3u);
  EXPECT_EQ(map.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(map.spawns.size(), 1u);
  EXPECT_EQ(map.spawns[0].position_m, Vec3(1, 0.5, -1));
  EXPECT_NEAR(map.spawns[0].yaw_rad, 3.14159265, 1e-6);
}

TEST(Map, AWallIsABoxAlongItsLine) {
  const Map map = parsed(kHeader + "wall -2 0 2 0  0 2 1\n" + kSpawn);
  physics::World world = physics::World::create(physics::profiles::arena_players()).value();
  ASSERT_TRUE(add_map_to_world(map, world).ok());
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
  std::string field;
  std::string message_part;
};

TEST(Map, ErrorsNameTheLineTheFieldAndWhatCame) {
  const BadMap cases[] = {
      {"", 0, "ricochet-map", "expected the version line"},
      {"name x\n", 1, "ricochet-map", "got 'name'"},
      {"ricochet-map 2\n", 1, "ricochet-map version", "expected 1, got '2'"},
      {"ricochet-map 1\nname bad/name\n", 2, "name", "got 'bad/name'"},
      {"ricochet-map 1\nname a\nname b\n", 3, "name", "got a second"},
      {"ricochet-map 1\nname a\nbox 0 0 0 1 1 1\n", 3, "box center", "'bounds' before"},
      {kHeader + "bounds 0 0 0 1 1 1\n", 4, "bounds", "got a second"},
      {"ricochet-map 1\nname a\nbounds 0 0 0 1 -1 1\n", 3, "bounds max.y", "more than min.y"},
      {kHeader + "box 0 0 0 1 -1 1\n", 4, "box half_extents.y", ">= 0.001000"},
      {kHeader + "box 0 0 0 1 1e-50 1\n", 4, "box half_extents.y", ">= 0.001000"},
      {kHeader + "wall 0 0 0 1e-40 0 2 0.5\n", 4, "wall x1", "at least 0.002000 m"},
      {kHeader + "box 0 0 0 1 0 1\n", 4, "box half_extents.y", "got '0'"},
      {kHeader + "box 0 0 0 1 1\n", 4, "box", "got 5 values"},
      {kHeader + "box 0 0 0 1 1 1 0 0\n", 4, "box", "got 8 values"},
      {kHeader + "box 0 0 0 1 1 x\n", 4, "box half_extents.z",
       "expected a decimal number, got 'x'"},
      {kHeader + "box 0 nan 0 1 1 1\n", 4, "box center.y", "got 'nan'"},
      {kHeader + "box 0 inf 0 1 1 1\n", 4, "box center.y", "got 'inf'"},
      {kHeader + "box 0 1e400 0 1 1 1\n", 4, "box center.y", "got '1e400'"},
      {kHeader + "box 0 1.5.2 0 1 1 1\n", 4, "box center.y", "got '1.5.2'"},
      {kHeader + "box 50 0 0 1 1 1\n", 4, "box center", "inside the bounds"},
      {kHeader + "box 0 0 0 1 1 1 400\n", 4, "box yaw", "<= 360"},
      {kHeader + "floor 20\n", 4, "floor y", "inside the bounds"},
      {kHeader + "floor 0\nfloor 1\n", 5, "floor", "got a second"},
      {kHeader + "wall 1 1 1 1 0 2 1\n", 4, "wall x1", "at least 0.002000 m from the start"},
      {kHeader + "wall 0 0 1 1 0 0 1\n", 4, "wall height", "got '0'"},
      {kHeader + "mesh r\nvertex 0 0 0\ntriangle 0 1 2\n", 6, "triangle b", "0..0"},
      {kHeader + "mesh r\ntriangle 0 0 0\n", 5, "triangle a", "'vertex' lines before"},
      {kHeader + "mesh r\nvertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\ntriangle 0 1 2\n", 8,
       "triangle", "degenerate"},
      {kHeader + "mesh r\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntriangle 0 0 2\n", 8,
       "triangle", "degenerate"},
      {kHeader + "mesh r\nvertex 0 0 0\ntriangle 0 -1 2\n", 6, "triangle b", "got '-1'"},
      {kHeader + "mesh r\nvertex 0 0 0\nend\n", 6, "end", "at least one triangle"},
      {kHeader + "mesh r\nbox 0 0 0 1 1 1\n", 5, "mesh r", "expected vertex, triangle or end"},
      {kHeader + "mesh r\nvertex 0 0 99\n", 5, "vertex", "inside the bounds"},
      {kHeader + "mesh r\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntriangle 0 1 2\n", 8, "end",
       "expected 'end' to close mesh r"},
      {kHeader + "mesh r/\n", 4, "mesh name", "got 'r/'"},
      {kHeader + "spawn 0 0 0\n", 4, "spawn", "got 3 values"},
      {kHeader + "spawn 0 -5 0 0\n", 4, "spawn position", "inside the bounds"},
      {kHeader, 0, "spawn", "at least one"},
      {"ricochet-map 1\nbounds 0 0 0 1 1 1\nspawn 0 0 0 0\n", 0, "name", "'name' line"},
      {"ricochet-map 1\nname a\nspawn 0 0 0 0\n", 3, "spawn position", "'bounds' before"},
      {kHeader + "teleporter 1 2 3\n", 4, "statement", "got 'teleporter'"},
      {kHeader + std::string(600, 'x') + "\n", 4, "line", "at most 512 characters, got 600"},
      {kHeader + "box 0 0 0 1 1 1 \x01\n", 4, "box yaw", "got '?'"},
  };
  for (const BadMap& bad : cases) {
    const MapError error = error_of(bad.text);
    EXPECT_EQ(error.line, bad.line) << bad.text << "\n" << error.describe();
    EXPECT_EQ(error.field, bad.field) << bad.text << "\n" << error.describe();
    EXPECT_NE(error.message.find(bad.message_part), std::string::npos) << bad.text << "\n"
                                                                       << error.describe();
  }
}

TEST(Map, DescribeSaysWhereAndWhat) {
  const MapError error = error_of(kHeader + "box 0 0 0 1 -1 1\n");
  EXPECT_EQ(error.describe(),
            "line 4: box half_extents.y: expected a number >= 0.001000 and <= 100000.000000, got "
            "'-1'");
}

TEST(Map, RefusesOversizedTextAndTooManyObjects) {
  EXPECT_EQ(error_of(std::string(kMaxMapBytes + 1, '\n')).field, "map");
  std::string many = kHeader;
  for (int k = 0; k < 1025; ++k) many += "box 0 0 0 1 1 1\n";
  const MapError boxes = error_of(many);
  EXPECT_EQ(boxes.line, 4 + 1024);
  EXPECT_NE(boxes.message.find("at most 1024 boxes"), std::string::npos);
  std::string spawns = kHeader;
  for (int k = 0; k < 65; ++k) spawns += kSpawn;
  EXPECT_NE(error_of(spawns).message.find("at most 64 spawns"), std::string::npos);
}

TEST(Map, AMissingFileIsAnError) {
  const MapResult result = load_map_file("/nonexistent/ricochet/none.map");
  ASSERT_TRUE(std::holds_alternative<MapError>(result));
  EXPECT_EQ(std::get<MapError>(result).field, "file");
}

TEST(Map, CommentsAndTabsAndCarriageReturnsAreWhitespace) {
  const Map map = parsed(
      "# header comment\r\nricochet-map 1\r\nname\tcrlf # trailing\r\n"
      "bounds -1 -1 -1 1 1 1\r\n\t spawn 0 0 0 0\r\n");
  EXPECT_EQ(map.name, "crlf");
  EXPECT_EQ(map.spawns.size(), 1u);
}

}  // namespace
}  // namespace ricochet::server
