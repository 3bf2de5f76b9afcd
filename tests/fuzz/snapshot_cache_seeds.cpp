// Writes the seed corpus of snapshot_cache_fuzz (the format is in snapshot_cache_input.h):
// scenes that reach every cache layer — many clients sharing baselines with everything fitting
// (streams), tight budgets that leave entities out (world baselines, walks, starts), lost and odd
// acknowledgements, encodes without the cache, mass removals, and each layer switched off. Run by
// `tools/fuzz.sh --seeds`; the output is committed in tests/fuzz/corpus/snapshot_cache/.
//
//   snapshot_cache_seeds DIR

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

struct Scene {
  std::uint8_t layers_off = 0;  ///< setup byte 0, bits 0..4
  int clients = 8;              ///< 1..8
  int stream_slots = 4;         ///< 1..4
  int ack_delay = 3;            ///< 1..6
  int budget = 1100;            ///< 24..1100
  int ticks = 48;
};

void put(std::string& out, int byte) {
  out.push_back(static_cast<char>(byte & 0xFF));
}

std::string setup(const Scene& scene) {
  std::string out;
  put(out, scene.layers_off | (scene.clients - 1) << 5);
  put(out, (scene.stream_slots - 1) | (scene.ack_delay - 1) << 2);
  put(out, (scene.budget - 24) >> 8);
  put(out, scene.budget - 24);
  return out;
}

/// Per tick: a crowd moves, one entity turns, one joins every `join_every` ticks and a few leave
/// at `removal_tick`; `client` writes each client's two bytes.
template <class Client>
std::string scene_bytes(const Scene& scene, int join_every, int removal_tick, Client&& client) {
  std::string out = setup(scene);
  for (int tick = 1; tick <= scene.ticks; ++tick) {
    const bool joins = join_every > 0 && tick % join_every == 0;
    const bool removes = tick == removal_tick;
    put(out, 2 + joins + (removes ? 4 : 0));
    put(out, 7), put(out, tick * 7), put(out, tick % 3), put(out, 3 + tick % 5);  // crowd moves
    put(out, 2), put(out, tick * 11), put(out, tick), put(out, tick * 3);         // a turn
    if (joins) put(out, 5), put(out, 0), put(out, tick), put(out, tick * 5);
    for (int k = 0; removes && k < 4; ++k) put(out, 4), put(out, k * 37), put(out, 0), put(out, 0);
    for (int c = 0; c < scene.clients; ++c) client(out, tick, c);
  }
  return out;
}

void write_file(const std::string& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir + "/" + name + ".bin";
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() ||
      std::fclose(file) != 0) {
    std::fprintf(stderr, "snapshot_cache_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  std::printf("%-28s %5zu bytes\n", name.c_str(), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: snapshot_cache_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  // Everything fits and every client acknowledges at one delay: streams are shared.
  const auto as_usual = [](std::string& out, int, int c) { put(out, 0), put(out, c * 9); };
  write_file(dir, "roomy_shared", scene_bytes(Scene{}, 4, 0, as_usual));
  // Budgets that leave entities out: clients hold the world but for a few, and follow walks.
  const Scene tight{.budget = 180, .ticks = 64};
  write_file(dir, "tight_walks", scene_bytes(tight, 1, 32, as_usual));
  // Every fourth tick roomy: bound clients holding the whole world start from one start.
  write_file(dir, "tight_then_roomy",
             scene_bytes(tight, 2, 0, [](std::string& out, int tick, int c) {
               put(out, tick % 4 == 0 ? 0xC0 : 0), put(out, c * 9);
             }));
  // Lost, late and odd acknowledgements, quarter budgets, encodes without the cache.
  write_file(dir, "mixed_clients",
             scene_bytes(Scene{.budget = 500}, 3, 30, [](std::string& out, int tick, int c) {
               const int mode = (tick + c) % 7 == 0 ? 2 : (tick * c) % 11 == 0 ? 3 : 0;
               put(out, mode | ((tick + c) % 16) << 2 | ((c % 3 == 1) ? 0x80 : 0));
               put(out, c * 9 | ((tick + c) % 9 == 0 ? 0xC0 : 0));
             }));
  // Many removals in a tick against budgets too small for all of them.
  write_file(
      dir, "mass_removal",
      scene_bytes(Scene{.clients = 6, .budget = 100}, 1, 20, [](std::string& out, int, int c) {
        put(out, c % 2 ? 0x80 : 0), put(out, c * 9);
      }));
  // Each layer switched off in turn, on the tight scene.
  const char* layers[] = {"streams", "deltas", "world_baselines", "walks", "whole_world_start"};
  for (int bit = 0; bit < 5; ++bit) {
    Scene off = tight;
    off.layers_off = static_cast<std::uint8_t>(1 << bit);
    off.stream_slots = 1 + bit % 4;
    write_file(dir, std::string("tight_without_") + layers[bit], scene_bytes(off, 1, 32, as_usual));
  }
  return 0;
}
