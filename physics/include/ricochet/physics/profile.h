#pragma once
/// Per-phase wall time of the last step, in milliseconds.

namespace ricochet::physics {

struct StepProfile {
  double broad_phase_ms = 0;   ///< find candidate pairs (grid for bodies, BVH for statics)
  double narrow_phase_ms = 0;  ///< contact points, normals, depths, warm-start matching
  double solve_ms = 0;         ///< prepare, warm start, iterations, restitution, store impulses
  double integrate_ms = 0;     ///< velocities and positions
  double continuous_ms = 0;    ///< swept tests for fast bodies
  double projectiles_ms = 0;   ///< projectile moves and sweeps
  double sleep_ms = 0;         ///< islands and sleeping
  double events_ms = 0;        ///< begin/end/impulse events
  double total_ms = 0;
  int bodies_awake = 0;
  int contacts = 0;         ///< contact constraints solved (including speculative ones)
  int pair_candidates = 0;  ///< body pairs tested by the narrowphase
  bool wide_simd = false;   ///< the contact solver ran its AVX2 path (WorldDef::wide_simd)
};

}  // namespace ricochet::physics
