// libFuzzer target: the TOML map parser (server/include/ricochet/server/map.h) on arbitrary bytes.
// The input is the map's text, then optionally a NUL byte and an OBJ text, which a stub reader
// serves for every `obj = "..."` the map names. It must never crash, hang or leak; a map it
// accepts must keep every promise of the format (server/maps/FORMAT.md: points inside the
// bounds, valid triangles, limits, team spawns), replay from its own files and build into a
// physics world.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/map.h"

namespace {

using ricochet::server::Map;
using ricochet::server::MapError;
using ricochet::server::Team;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void check_accepted(const Map& map, std::string_view text) {
  require(!map.name.empty() && map.name.size() <= 32);
  require(!map.spawns.empty() && map.spawns.size() <= 64);
  require((map.bounds_max_m.array() > map.bounds_min_m.array()).all());
  if (map.floor_y_m) {
    require(*map.floor_y_m >= map.bounds_min_m.y() && *map.floor_y_m <= map.bounds_max_m.y());
  }
  std::size_t teams[3] = {0, 0, 0};
  for (const auto& spawn : map.spawns) {
    require(map.contains(spawn.position_m));
    require(static_cast<std::size_t>(spawn.team) < 3);
    ++teams[static_cast<std::size_t>(spawn.team)];
    for (const auto& volume : map.kill_volumes) require(!volume.contains(spawn.position_m));
  }
  require((teams[1] == 0) == (teams[2] == 0));
  require(map.boxes.size() <= 1024);
  for (const auto& box : map.boxes) {
    require(map.contains(box.center_m));
    require((box.half_extents_m.array() > 0).all());
  }
  require(map.meshes.size() <= 64);
  for (const auto& mesh : map.meshes) {
    require(!mesh.indices.empty() && mesh.indices.size() % 3 == 0);
    for (const std::uint32_t index : mesh.indices) require(index < mesh.vertices_m.size());
    for (const auto& vertex : mesh.vertices_m) require(map.contains(vertex));
  }
  for (const auto& pickup : map.pickups) {
    require(map.contains(pickup.position_m));
    const int most = pickup.kind == ricochet::server::PickupKind::Ammo ? 100 : 200;
    require(pickup.amount >= 1 && pickup.amount <= most);
    require(pickup.respawn_s >= 1 && pickup.respawn_s <= 600);
  }
  for (const auto& volume : map.kill_volumes) {
    require(map.contains(volume.min_m) && map.contains(volume.max_m));
    require((volume.max_m.array() > volume.min_m.array()).all());
  }
  require(!map.files.empty() && map.files[0].text == text && map.files.size() <= 17);

  // The recorded files give the same map again.
  const ricochet::server::MapResult again = ricochet::server::parse_map_files(map.files);
  const Map* replayed = std::get_if<Map>(&again);
  require(replayed != nullptr);
  require(replayed->boxes.size() == map.boxes.size() &&
          replayed->meshes.size() == map.meshes.size() &&
          replayed->spawns.size() == map.spawns.size() &&
          replayed->pickups.size() == map.pickups.size() &&
          replayed->kill_volumes.size() == map.kill_volumes.size() &&
          replayed->files.size() == map.files.size());

  ricochet::physics::World world =
      ricochet::physics::World::create(ricochet::physics::profiles::arena_players()).value();
  require(ricochet::server::add_map_to_world(map, world).ok());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t cut = input.find('\0');
  const std::string_view text = input.substr(0, cut);
  const std::string obj(cut == std::string_view::npos ? std::string_view() : input.substr(cut + 1));
  const ricochet::server::MapFileReader read = [&obj](std::string_view, std::string&) {
    return std::optional<std::string>(obj);
  };
  const ricochet::server::MapResult result = ricochet::server::parse_map(text, "fuzz.toml", read);
  if (const Map* map = std::get_if<Map>(&result)) {
    check_accepted(*map, text);
  } else {
    const auto& error = std::get<MapError>(result);
    require(!error.file.empty() && !error.item.empty() && !error.message.empty() &&
            error.line >= 0);
  }
  return 0;
}
