#pragma once
/// Random worlds of quantised entities for the snapshot codec's tests.

#include <algorithm>
#include <random>
#include <vector>

#include "ricochet/proto/quantize.h"

namespace ricochet::proto::test {

inline QuantizationSpec test_spec() {
  QuantizationSpec spec;
  spec.bounds = {{-40.0f, -2.0f, -40.0f}, {40.0f, 30.0f, 40.0f}};
  return spec;
}

/// A random state anywhere in the spec's ranges; `rotates` decides whether it has an orientation.
inline QuantizedEntity random_entity(std::uint32_t id, const QuantizationSpec& spec,
                                     std::mt19937& random, bool rotates) {
  EntityState state;
  state.id = id;
  std::normal_distribution<float> normal;
  for (int a = 0; a < 3; ++a) {
    std::uniform_real_distribution<float> axis(spec.bounds.min_m[a], spec.bounds.max_m[a]);
    state.position_m[a] = axis(random);
    state.velocity_mps[a] = (random() % 3 == 0) ? 0.0f : 5 * normal(random);
  }
  if (rotates) {
    float norm = 0;
    for (float& c : state.orientation_xyzw) {
      c = normal(random);
      norm += c * c;
    }
    for (float& c : state.orientation_xyzw) c /= std::sqrt(norm);
  }
  state.flags = static_cast<std::uint8_t>(random() % 4 == 0 ? random() : 0);
  return quantize(state, spec);
}

/// Moves about a fifth of the entities by small random steps, as a physics tick would.
inline void perturb(std::vector<QuantizedEntity>& world, const QuantizationSpec& spec,
                    std::mt19937& random) {
  for (QuantizedEntity& e : world) {
    if (random() % 5 != 0) continue;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t step = static_cast<std::int64_t>(random() % 401) - 200;
      e.position[a] = static_cast<std::uint32_t>(std::clamp<std::int64_t>(
          static_cast<std::int64_t>(e.position[a]) + step, 0, spec.position_steps(a) - 1));
      e.velocity[a] = std::clamp<std::int32_t>(e.velocity[a] + static_cast<int>(random() % 21) - 10,
                                               -spec.velocity_limit(), spec.velocity_limit());
    }
    if (random() % 3 == 0 && e.orientation_largest == 3) {
      e.orientation[random() % 3] = static_cast<std::int32_t>(random() % 200) - 100;
    }
    if (random() % 50 == 0) e.flags ^= 1;
  }
}

/// Moves one entity anywhere with any velocity (a respawn): its delta is far longer than the
/// others', which is the case the encoder writes field by field (layout::DeltaBody overflow).
inline void teleport(std::vector<QuantizedEntity>& world, const QuantizationSpec& spec,
                     std::mt19937& random) {
  if (world.empty()) return;
  QuantizedEntity& e = world[random() % world.size()];
  const QuantizedEntity moved = random_entity(e.id, spec, random, e.orientation_largest != 3);
  e.position = moved.position;
  for (int a = 0; a < 3; ++a) {
    e.velocity[a] = random() % 2 ? spec.velocity_limit() : -spec.velocity_limit();
  }
}

inline std::vector<QuantizedEntity> random_world(std::size_t count, const QuantizationSpec& spec,
                                                 std::mt19937& random) {
  std::vector<QuantizedEntity> world;
  std::uint32_t id = 1;
  for (std::size_t i = 0; i < count; ++i) {
    id += 1 + static_cast<std::uint32_t>(random() % 3);
    world.push_back(random_entity(id, spec, random, random() % 2 == 0));
  }
  return world;
}

}  // namespace ricochet::proto::test
