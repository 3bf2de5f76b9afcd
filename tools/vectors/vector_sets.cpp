#include <array>

#include "vector_file.h"

namespace ricochet::vectors {

// One writer per *_vectors.cpp file.
std::string write_control_frames_vectors();
std::string write_game_packets_vectors();
std::string write_control_session_vectors();
std::string write_snapshots_spheres901_vectors();
std::string write_snapshots_players64_vectors();
std::string write_movement_arena_vectors();
std::string write_movement_foundry_vectors();

std::span<const VectorSet> vector_sets() {
  static constexpr std::array kSets = {
      VectorSet{"control_frames", &write_control_frames_vectors},
      VectorSet{"game_packets", &write_game_packets_vectors},
      VectorSet{"control_session", &write_control_session_vectors},
      VectorSet{"snapshots_spheres901", &write_snapshots_spheres901_vectors},
      VectorSet{"snapshots_players64", &write_snapshots_players64_vectors},
      VectorSet{"movement_arena", &write_movement_arena_vectors},
      VectorSet{"movement_foundry", &write_movement_foundry_vectors},
  };
  return kSets;
}

}  // namespace ricochet::vectors
