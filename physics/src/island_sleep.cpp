/// Islands and sleeping. Islands are recomputed every step by union-find over the broadphase's
/// body pairs (bodies within contact reach), so nothing about islands needs to persist:
///   - before the narrowphase, an island holding any awake body wakes entirely;
///   - after the solve, an island whose every body has been slow for time_to_sleep sleeps.
/// Static geometry, kinematic and frozen bodies do not join islands.

#include <algorithm>

#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];  // path halving
    x = parent[x];
  }
  return x;
}

void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b) std::swap(a, b);
  parent[a] = b;  // smaller slot is the root: deterministic
}

}  // namespace

void WorldImpl::wake_body(std::uint32_t slot) {
  if (state.bodies.has(slot, kFlagSleeping)) mark_for_move_event(slot, kMoveMarkWoke);
  state.bodies.flags[slot] &= static_cast<std::uint16_t>(~kFlagSleeping);
  state.bodies.sleep_time[slot] = 0;
}

void WorldImpl::wake_touching_islands() {
  if (!def.enable_sleep) return;
  const std::uint32_t slots = state.bodies.slot_count();
  scratch.island_parent.resize(slots);
  for (std::uint32_t s = 0; s < slots; ++s) scratch.island_parent[s] = s;
  constexpr std::uint16_t kNotLinking = kFlagKinematic | kFlagFrozen;
  std::vector<std::uint8_t>& root_awake = scratch.island_scratch;
  assign_reusing(root_awake, slots, 0);
  for (const BodyPair& pair : scratch.pairs) {
    const std::uint16_t fa = state.bodies.flags[pair.a], fb = state.bodies.flags[pair.b];
    if (((fa | fb) & kNotLinking) == 0) {
      unite(scratch.island_parent, pair.a, pair.b);
      continue;
    }
    // A moving kinematic body wakes what it reaches.
    const auto kinematic_moving = [&](std::uint32_t s) {
      return state.bodies.has(s, kFlagKinematic) &&
             !state.bodies.motion[s].linear_velocity.isZero(0);
    };
    if (kinematic_moving(pair.a) && state.bodies.has(pair.b, kFlagSleeping)) wake_body(pair.b);
    if (kinematic_moving(pair.b) && state.bodies.has(pair.a, kFlagSleeping)) wake_body(pair.a);
  }
  for (std::uint32_t s = 0; s < slots; ++s) {
    if (state.bodies.alive(s) && !state.bodies.has(s, kFlagSleeping) &&
        !state.bodies.has(s, kNotLinking)) {
      root_awake[find_root(scratch.island_parent, s)] = 1;
    }
  }
  for (std::uint32_t s = 0; s < slots; ++s) {
    if (state.bodies.has(s, kFlagSleeping) && state.bodies.alive(s) &&
        root_awake[find_root(scratch.island_parent, s)]) {
      wake_body(s);
    }
  }
}

void WorldImpl::update_sleep(Real step_dt) {
  if (!def.enable_sleep) return;
  const Real linear2 = def.sleep_linear_speed * def.sleep_linear_speed;
  const Real angular2 = def.sleep_angular_speed * def.sleep_angular_speed;
  for (const std::uint32_t s : scratch.awake_list) {
    if (!state.bodies.simulated(s)) continue;
    const Motion& m = state.bodies.motion[s];
    const bool slow = state.bodies.has(s, kFlagAllowSleep) &&
                      m.linear_velocity.squaredNorm() < linear2 &&
                      m.angular_velocity.squaredNorm() < angular2;
    state.bodies.sleep_time[s] = slow ? state.bodies.sleep_time[s] + step_dt : Real(0);
  }
  // Bodies carried or pushed by a moving kinematic body stay awake.
  for (const Contact& c : state.pair_contacts) {
    const bool a_kinematic = state.bodies.has(c.a, kFlagKinematic),
               b_kinematic = state.bodies.has(c.b, kFlagKinematic);
    if (a_kinematic && !state.bodies.motion[c.a].linear_velocity.isZero(0))
      state.bodies.sleep_time[c.b] = 0;
    if (b_kinematic && !state.bodies.motion[c.b].linear_velocity.isZero(0))
      state.bodies.sleep_time[c.a] = 0;
  }
  // An island sleeps when its slowest-to-settle body has been slow long enough.
  const std::uint32_t slots = state.bodies.slot_count();
  std::vector<Real>& island_min_time = scratch.island_sleep_time;
  assign_reusing(island_min_time, slots, std::numeric_limits<Real>::max());
  for (const std::uint32_t s : scratch.awake_list) {
    if (!state.bodies.simulated(s)) continue;
    Real& t = island_min_time[find_root(scratch.island_parent, s)];
    t = std::min(t, state.bodies.sleep_time[s]);
  }
  for (const std::uint32_t s : scratch.awake_list) {
    if (!state.bodies.simulated(s)) continue;
    if (island_min_time[find_root(scratch.island_parent, s)] < def.time_to_sleep) continue;
    state.bodies.flags[s] |= kFlagSleeping;
    state.bodies.motion[s].linear_velocity.setZero();
    state.bodies.motion[s].angular_velocity.setZero();
  }
}

}  // namespace ricochet::physics
