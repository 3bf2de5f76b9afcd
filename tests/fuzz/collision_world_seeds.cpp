// Writes the seed corpus of collision_world_fuzz: the small world of the bot's tests (a floor, a
// turned wall, a ramp), the same with each kind of shape alone, and a few refused ones (a NaN,
// an index past the vertices, no movement rules). Run by `tools/fuzz.sh --seeds`; the output is
// committed in tests/fuzz/corpus/collision_world/.
//
//   collision_world_seeds DIR

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "collision_world_fixture.h"

namespace {

using ricochet::wire::CollisionWorld;

void write_file(const std::string& dir, const std::string& name, const CollisionWorld& world) {
  const std::string bytes = world.SerializeAsString();
  const std::string path = dir + "/" + name + ".bin";
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() ||
      std::fclose(file) != 0) {
    std::fprintf(stderr, "collision_world_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  std::printf("%-24s %5zu bytes\n", name.c_str(), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: collision_world_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const CollisionWorld arena = ricochet::bot::testing::arena_world();
  write_file(dir, "arena", arena);
  CollisionWorld only = arena;
  only.clear_boxes();
  only.clear_meshes();
  write_file(dir, "floor_only", only);
  only = arena;
  only.clear_planes();
  only.clear_meshes();
  write_file(dir, "box_only", only);
  only = arena;
  only.clear_planes();
  only.clear_boxes();
  write_file(dir, "mesh_only", only);
  CollisionWorld bad = arena;
  bad.mutable_meshes(0)->set_vertices_m(4, std::nanf(""));
  write_file(dir, "nan_vertex", bad);
  bad = arena;
  bad.mutable_meshes(0)->set_indices(2, 40);
  write_file(dir, "index_past_end", bad);
  bad = arena;
  bad.clear_movement();
  write_file(dir, "no_movement", bad);
  return 0;
}
