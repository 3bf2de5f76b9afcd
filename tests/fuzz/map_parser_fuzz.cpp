// libFuzzer target: the map text parser (server/include/ricochet/server/map.h) on arbitrary
// bytes. It must never crash, hang or leak; a map it accepts must keep every promise of the
// format (points inside the bounds, valid triangles, limits) and build into a physics world.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/map.h"

namespace {

using ricochet::server::Map;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void check_accepted(const Map& map) {
  require(!map.name.empty() && map.name.size() <= 32);
  require(!map.spawns.empty() && map.spawns.size() <= 64);
  require((map.bounds_max_m.array() > map.bounds_min_m.array()).all());
  for (const auto& spawn : map.spawns) require(map.contains(spawn.position_m));
  for (const auto& box : map.boxes) {
    require(map.contains(box.center_m));
    require((box.half_extents_m.array() > 0).all());
  }
  for (const auto& mesh : map.meshes) {
    require(!mesh.indices.empty() && mesh.indices.size() % 3 == 0);
    for (const std::uint32_t index : mesh.indices) require(index < mesh.vertices_m.size());
    for (const auto& vertex : mesh.vertices_m) require(map.contains(vertex));
  }
  ricochet::physics::World world =
      ricochet::physics::World::create(ricochet::physics::profiles::arena_players()).value();
  require(ricochet::server::add_map_to_world(map, world).ok());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const ricochet::server::MapResult result = ricochet::server::parse_map(text);
  if (const Map* map = std::get_if<Map>(&result)) {
    check_accepted(*map);
  } else {
    const auto& error = std::get<ricochet::server::MapError>(result);
    require(!error.field.empty() && !error.message.empty() && error.line >= 0);
  }
  return 0;
}
