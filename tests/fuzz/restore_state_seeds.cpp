// Writes the seed corpus of restore_state_fuzz: valid images of the fuzz world and of the stack
// world (fuzz_world.h) at a few moments. Run by `tools/fuzz.sh --seeds`; the output is committed
// in tests/fuzz/corpus/restore_state/.
//
//   restore_state_seeds DIR

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_world.h"

namespace {

using namespace ricochet::physics;
using fuzz::must;

void step(World& world, int steps) {
  for (int i = 0; i < steps; ++i) must(world.step(fuzz::kDt), "step");
}

int sleeping_bodies(const World& world) {
  int sleeping = 0;
  // Bodies that were never destroyed sit in slot k with generation 1; a destroyed slot fails.
  for (std::uint32_t k = 0; k < 64; ++k) {
    const Result<BodyState> state = world.body_state(BodyId{k, 1});
    sleeping += state.ok() && state.value().sleeping ? 1 : 0;
  }
  return sleeping;
}

struct Writer {
  std::string dir;
  int written = 0;

  /// Saves both parts of `world` as NAME_all and NAME_dynamic, after checking that each restores
  /// into a fresh world built by `make` (the All image also into an empty world).
  void save(const World& world, World (*make)(), const std::string& name) {
    for (const StateParts parts : {StateParts::All, StateParts::Dynamic}) {
      std::vector<std::uint8_t> image;
      world.save_state(image, parts);
      World fresh = make();
      must(fresh.restore_state(image), "restore_state into a fresh world");
      if (parts == StateParts::All) {
        World empty = must(World::create(fuzz::fuzz_world_def()), "World::create");
        must(empty.restore_state(image), "restore_state into an empty world");
      }
      const std::string path =
          dir + "/" + name + (parts == StateParts::All ? "_all" : "_dynamic") + ".bin";
      std::FILE* file = std::fopen(path.c_str(), "wb");
      if (!file || std::fwrite(image.data(), 1, image.size(), file) != image.size() ||
          std::fclose(file) != 0) {
        std::fprintf(stderr, "restore_state_seeds: cannot write %s\n", path.c_str());
        std::exit(1);
      }
      std::printf("%-28s %5zu bytes, %u bodies, %d sleeping, %u projectiles\n",
                  (name + (parts == StateParts::All ? "_all" : "_dynamic")).c_str(), image.size(),
                  world.body_count(), sleeping_bodies(world), world.projectile_count());
      ++written;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: restore_state_seeds DIR\n");
    return 2;
  }
  Writer out{argv[1]};

  World world = fuzz::make_fuzz_world();
  out.save(world, fuzz::make_fuzz_world, "fuzz_step0");
  step(world, 1);
  // Loads for the next step, which the image carries: a force on the falling ball (slot 0) and a
  // torque on the ball on the box (slot 1).
  must(world.apply_force(BodyId{0, 1}, Vec3(1, 2, 3)), "apply_force");
  must(world.apply_torque(BodyId{1, 1}, Vec3(0, Real(0.5), 0)), "apply_torque");
  out.save(world, fuzz::make_fuzz_world, "fuzz_step1");
  step(world, 29);
  out.save(world, fuzz::make_fuzz_world, "fuzz_step30");
  // Settled: balls resting on the floor, the box and the ramp's foot; the falling ball inside
  // the sensor; some asleep.
  step(world, 270);
  out.save(world, fuzz::make_fuzz_world, "fuzz_step300");

  World stack = fuzz::make_stack_world();
  step(stack, 240);
  out.save(stack, fuzz::make_stack_world, "stack_step240");
  if (sleeping_bodies(stack) == 0) {
    std::fprintf(stderr, "restore_state_seeds: the stack did not fall asleep\n");
    return 1;
  }
  std::printf("restore_state_seeds: wrote %d images to %s\n", out.written, out.dir.c_str());
  return 0;
}
