// Writes the seed corpus of map_parser_fuzz: the shipped maps (the foundry with its OBJ after a
// NUL byte, as the fuzzer reads it) and small maps that use every key, each checked to parse
// as intended. Run by `tools/fuzz.sh --seeds` from the repo root; the output is committed in
// tests/fuzz/corpus/map_parser/.
//
//   map_parser_seeds DIR

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/server/map.h"

namespace {

struct Seed {
  const char* name;
  std::string map;
  std::string obj;  ///< served for every obj = "..." the map names
  bool valid;
};

const std::string kHeader =
    "format = 1\nname = \"m\"\n[bounds]\nmin = [-10, -2, -10]\nmax = [10, 8, 10]\n";

Seed small_seeds[] = {
    {"minimal", kHeader + "[[spawn]]\nposition = [0, 0, 0]\n", "", true},
    {"every_key",
     "# every key once\nformat = 1\nname = \"every-key_1\"\nfloor_y = 0\n"
     "[bounds]\nmin = [-10, -2, -10]\nmax = [10, 8, 10]\n"
     "[[box]]\ncenter = [1, 1, 1]\nhalf_extents = [0.5, 1, 0.5]\nyaw_deg = 45\n"
     "[[wall]]\nfrom = [-5, -5]\nto = [5, -5]\nbase = 0\nheight = 3\nthickness = 0.2\n"
     "[[mesh]]\nname = \"ramp\"\nvertices = [[0, 0, 0], [0, 0, 2], [4, 1.5, 2], [4, 1.5, 0]]\n"
     "triangles = [[0, 1, 2], [0, 2, 3]]\n"
     "[[mesh]]\nname = \"stairs\"\nobj = \"stairs.obj\"\n"
     "[[spawn]]\nposition = [0, 0.45, 0]\nyaw_deg = 90\nteam = \"red\"\n"
     "[[spawn]]\nposition = [2, 0.45, -2]\nyaw_deg = -90.5\nteam = \"blue\"\n"
     "[[spawn]]\nposition = [-2, 0.45, 2]\n"
     "[[pickup]]\nkind = \"health\"\nposition = [3, 0.5, 3]\namount = 25\nrespawn_s = 20\n"
     "[[pickup]]\nkind = \"armor\"\nposition = [-3, 0.5, 3]\namount = 50\nrespawn_s = 30.5\n"
     "[[pickup]]\nkind = \"ammo\"\nposition = [3, 0.5, -3]\namount = 20\nrespawn_s = 15\n"
     "[[kill_volume]]\nname = \"below\"\nmin = [-10, -2, -10]\nmax = [10, -1, 10]\n",
     "o stairs\nv 0 0 5\nv 1 0 5\nv 1 1 6\nv 0 1 6\nvt 0 0\nvn 0 1 0\n"
     "f 1/1/1 2/1/1 3//1 4//1\nf -1 -2 -4\n",
     true},
    {"inline_tables_crlf",
     "format = 1\r\nname = 'crlf'\r\nbounds = { min = [-5, -5, -5], max = [5, 5, 5] }\r\n"
     "spawn = [{ position = [1, 2, 3], yaw_deg = -360 }]\r\n"
     "box = [{ center = [0, 0, 0], half_extents = [1e0, 0.5, 1.5e-1] }]\r\n",
     "", true},
    {"bad_triangle",
     kHeader + "[[mesh]]\nname = \"x\"\nvertices = [[0, 0, 0]]\ntriangles = [[0, 0, 0]]\n"
               "[[spawn]]\nposition = [0, 0, 0]\n",
     "", false},
    {"bad_obj_index",
     kHeader + "[[mesh]]\nname = \"x\"\nobj = \"x.obj\"\n[[spawn]]\nposition = [0, 0, 0]\n",
     "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 -4\n", false},
};

std::string read_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    std::fprintf(stderr, "map_parser_seeds: run from the repo root (cannot read %s)\n",
                 path.c_str());
    std::exit(1);
  }
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

void write(const std::string& path, const std::string& text) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || std::fwrite(text.data(), 1, text.size(), file) != text.size() ||
      std::fclose(file) != 0) {
    std::fprintf(stderr, "map_parser_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

/// The fuzzer's input: the map, then a NUL and the OBJ text when there is one.
std::string input(const Seed& seed) {
  return seed.obj.empty() ? seed.map : seed.map + std::string(1, '\0') + seed.obj;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: map_parser_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  std::vector<Seed> seeds = {
      {"arena", read_file("server/maps/arena.toml"), "", true},
      {"foundry", read_file("server/maps/foundry.toml"), read_file("server/maps/foundry_ramps.obj"),
       true},
  };
  seeds.insert(seeds.end(), std::begin(small_seeds), std::end(small_seeds));
  for (const Seed& seed : seeds) {
    const std::string obj = seed.obj;
    const ricochet::server::MapFileReader read = [&obj](std::string_view, std::string&) {
      return std::optional<std::string>(obj);
    };
    const ricochet::server::MapResult result = ricochet::server::parse_map(seed.map, "seed", read);
    if (std::holds_alternative<ricochet::server::Map>(result) != seed.valid) {
      std::fprintf(
          stderr, "map_parser_seeds: seed %s parses=%d, not as intended: %s\n", seed.name,
          !seed.valid,
          seed.valid ? std::get<ricochet::server::MapError>(result).describe().c_str() : "");
      return 1;
    }
    write(dir + "/" + seed.name + ".toml", input(seed));
  }
  std::printf("map_parser_seeds: wrote %zu seeds\n", seeds.size());
  return 0;
}
