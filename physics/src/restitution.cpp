/// Restitution, after the contact solve: impacts as a sequence of pairwise collisions, in the
/// manner of Guendelman, Bridson and Fedkiw's collision processing (2003).
///
/// The solve treats every contact as inelastic (e = 0) and, being simultaneous, spreads an impact
/// over every body the struck one touches: a ball striking a touching row (Newton's cradle)
/// leaves the whole row moving at a common velocity. Reflecting only the contacts that were
/// approaching at step start then sends the striker back and the row forward together, and the
/// energy is lost. Instead, this pass replays the step's impacts one collision at a time:
///
///   1. velocities without the step's normal impulses of the contacts that can bounce (e > 0,
///      touched this step): the collision velocities X;
///   2. the contacts that approached faster than restitution_threshold at step start collide in
///      X; each collision pushes the pair apart at e times its approach speed (impact-phase aware,
///      see departure_speed); a contact whose bodies a collision moved is checked again, and
///      collides in turn if it now approaches faster than the threshold (first in, first out,
///      so the impulse travels down a chain in order);
///   3. each contact that collided replaces the solve's normal impulse by its collision impulses;
///   4. the contacts around the bodies this moved are solved again at velocity level, inelastic,
///      each towards the relative velocity the solve left it with, so a body supported by
///      contacts that did not collide is not launched by the support the solve gave it against
///      the impact: Gauss–Seidel passes over them (as many as the solver's iterations) until
///      one changes no contact's relative velocity by more than a tolerance.
///
/// A contact that collided warm-starts the next step with what step 4 added on top of its
/// collision impulses: the support it carries (a pile's weight), not the impact, which the next
/// solve would have to take back (a chain does so only approximately). With one clean-up pass
/// and no warm start, a pile struck step after step rebuilt its support from zero each time and
/// sank into itself (the rain bench at 16384 spheres and 300 steps, results/rain-large.jsonl;
/// tests/physics/rain_pile_test.cpp).
///
/// A step without a fast approach changes nothing, so resting contacts and stacks behave as
/// without restitution. The pass costs one read of every contact lane to find the fast
/// approaches and, when there are some, one more to list each body's touched contacts; all else
/// is proportional to the impact region (the contacts queued and the bodies they move).

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

/// Departure velocity that keeps energy across the impact's phase inside the step. The stored
/// velocity of a semi-implicit body is the mean over the step it just took, ½·a·h off its true
/// value, and the impact happens somewhere inside the step; reflecting the stored approach speed
/// loses up to 2·a·h per bounce. Per contact with relative normal velocity v at step start,
/// relative normal acceleration a (constant over the step), gap d at step start and d' at the end:
///   true approach at the step start  w  = v + s·½·a·h   (s = +1 semi-implicit, -1 explicit)
///   approach at the moment of touch  wc = -√(w² - 2·a·d)            (constant-acceleration fall)
///   departure at the touch           wo = e·|wc|, and at the end √(wo² + 2·a·d')
///   stored departure velocity        v' = √(wo² + 2·a·d') - s·½·a·h
/// so ½·w² + a·gap, which semi-implicit Euler conserves exactly under constant acceleration, is
/// scaled by e² and nothing else.
Real departure_speed(Real v, Real a, Real half_h, Real gap, Real end_gap, Real e) {
  const Real w = v + half_h * a;
  const Real touch = std::sqrt(std::max(w * w - 2 * a * gap, Real(0)));
  const Real departure = e * touch;
  return std::sqrt(std::max(departure * departure + 2 * a * end_gap, Real(0))) - half_h * a;
}

/// One step's collision pass (steps 1 to 4 above) over the touched contacts. The loops work
/// through local pointers: a store to a flag byte may alias anything, so a vector's data pointer
/// would be reloaded after each one.
class CollisionPass {
 public:
  CollisionPass(SolverScratch& s, Real threshold, Real h, Real half_h, int substeps)
      : s_(s),
        r_(s.restitution),
        threshold_(threshold),
        h_(h),
        half_h_(half_h),
        substeps_(static_cast<Real>(substeps)) {}

  /// True if some contact can bounce and approached faster than the threshold at step start.
  bool any_fast_approach() const {
    for (std::size_t k = 0; k < s_.blocks.size(); ++k) {
      const ContactBlock& c = s_.blocks[k];
      const ContactBlockExtra& e = s_.extra[k];
      bool fast = false;
      for (int l = 0; l < kLanes; ++l) {
        fast = fast || (e.relative_velocity[l] <= -threshold_ && e.restitution[l] != 0 &&
                        c.max_normal_impulse[l] > 0);
      }
      if (fast) return true;
    }
    return false;
  }

  /// Copies the touched contacts in lane order and lists each body's; takes the collision
  /// velocities (step 1) and queues the fast approaches, both in lane order.
  void gather_contacts() {
    const std::size_t body_count = s_.bodies.size();
    const std::size_t lanes = s_.blocks.size() * kLanes;
    if (r_.touched.size() < lanes) {
      r_.touched.resize(lanes);
      r_.state.resize(lanes);
      r_.flags.resize(lanes);
    }
    assign_reusing(r_.start, body_count + 2, 0);
    assign_reusing(r_.targets_taken, body_count, 0);
    r_.velocity.resize(body_count);
    r_.queue.clear();
    const Motion* const bodies = s_.bodies.data();
    Vec3* const x = r_.velocity.data();
    Touched* const touched = r_.touched.data();
    TouchedState* const state = r_.state.data();
    std::uint8_t* const flags = r_.flags.data();
    std::uint32_t* const start = r_.start.data();
    for (std::size_t k = 0; k < body_count; ++k) x[k] = bodies[k].linear_velocity;
    std::uint32_t count = 0;
    for (std::size_t k = 0; k < s_.blocks.size(); ++k) {
      const ContactBlock& c = s_.blocks[k];
      const ContactBlockExtra& e = s_.extra[k];
      Real max_impulse[kLanes];
      std::memcpy(max_impulse, &c.max_normal_impulse, sizeof max_impulse);
      unsigned lanes_touched = 0;
      for (int l = 0; l < kLanes; ++l)
        lanes_touched |= static_cast<unsigned>(max_impulse[l] != 0) << l;
      for (; lanes_touched != 0; lanes_touched &= lanes_touched - 1, ++count) {
        const int l = std::countr_zero(lanes_touched);
        const std::uint32_t a = c.a[l], b = c.b[l];
        const Vec3 n(c.nx[l], c.ny[l], c.nz[l]);
        const Real restitution = e.restitution[l];
        const Real relative_velocity = e.relative_velocity[l];
        const Real p = e.total_normal_impulse[l];
        touched[count] = {a, b, n};
        TouchedState& t = state[count];
        t.where = static_cast<std::uint32_t>(k * kLanes) + static_cast<std::uint32_t>(l);
        t.separation = c.separation[l];
        t.normal_mass = c.normal_mass[l];
        t.relative_velocity = relative_velocity;
        t.restitution = restitution;
        t.total_normal_impulse = p;
        t.collision = -1;
        t.applied = 0;
        ++start[a + 2];
        ++start[b + 2];
        const bool bounces = restitution != 0 && c.max_normal_impulse[l] > 0;
        flags[count] = bounces ? RestitutionScratch::kBounces : 0;
        if (!bounces) continue;
        x[a] += (bodies[a].inverse_mass * p) * n;
        x[b] -= (bodies[b].inverse_mass * p) * n;
        if (relative_velocity <= -threshold_) {
          flags[count] |= RestitutionScratch::kFast | RestitutionScratch::kQueued;
          r_.queue.push_back(count);
        }
      }
    }
    r_.touched_count = count;
    for (std::size_t k = 2; k < body_count + 2; ++k) start[k] += start[k - 1];
    r_.adjacent.resize(2 * static_cast<std::size_t>(count));
    std::uint32_t* const adjacent = r_.adjacent.data();
    for (std::uint32_t i = 0; i < count; ++i) {
      adjacent[start[touched[i].a + 1]++] = 2 * i;
      adjacent[start[touched[i].b + 1]++] = 2 * i + 1;
    }
    assign_reusing(r_.collided, (count + 63) / 64, 0);
  }

  /// 2. Collisions in sequence, first in, first out.
  void replay_collisions() {
    const std::size_t lanes = s_.blocks.size() * kLanes;
    // Every collision moves energy on or loses it, so this ends; the cap is for float rounding.
    const std::size_t max_collisions = 16 * lanes + 16;
    const Motion* const bodies = s_.bodies.data();
    const Vec3* const delta_position = s_.delta_position.data();
    Vec3* const x = r_.velocity.data();
    const Touched* const touched = r_.touched.data();
    TouchedState* const state = r_.state.data();
    std::uint8_t* const flags = r_.flags.data();
    std::size_t collisions = 0;
    for (std::size_t head = 0; head < r_.queue.size() && collisions < max_collisions; ++head) {
      const std::uint32_t i = r_.queue[head];
      flags[i] &= ~RestitutionScratch::kQueued;
      const Vec3 n = touched[i].normal;
      const std::uint32_t a = touched[i].a, b = touched[i].b;
      const Real vn = n.dot(x[b] - x[a]);
      // Not collided yet (its collision impulse is then < 0) and fast at step start.
      const bool first = !(flags[i] & RestitutionScratch::kCollided);
      const bool seed = first && (flags[i] & RestitutionScratch::kFast);
      if (!seed && !(vn <= -threshold_)) continue;
      TouchedState& c = state[i];
      const Real accel = n.dot(acceleration(b) - acceleration(a));
      const Real v = seed ? c.relative_velocity : vn - accel * h_;  // approach at step start
      const Real gap = first ? std::max(c.separation, Real(0)) : Real(0);
      const Real end_gap =
          std::max(c.separation + n.dot(delta_position[b] - delta_position[a]), Real(0));
      const Real target = departure_speed(v, accel, half_h_, gap, end_gap, c.restitution);
      const Real impulse = std::max(c.normal_mass * (target - vn), Real(0));
      c.collision = std::max(c.collision, Real(0)) + impulse;
      if (first) {
        r_.collided[i / 64] |= std::uint64_t(1) << (i % 64);
        flags[i] |= RestitutionScratch::kCollided;
      }
      ++collisions;
      if (impulse == 0) continue;
      x[a] -= (bodies[a].inverse_mass * impulse) * n;
      x[b] += (bodies[b].inverse_mass * impulse) * n;
      queue_bouncing_neighbours(a);
      queue_bouncing_neighbours(b);
    }
  }

  /// 4 (targets first), then 3. Every touched contact around a body of a contact that collided
  /// is queued for the clean-up with the relative velocity to keep, taken before step 3 moves
  /// anything: a contact that collided towards not approaching, with no less than its collision
  /// impulse; any other towards what the solve left it with, with no less than none.
  void replace_impulses() {
    r_.queue.clear();
    for_each_collided([&](std::uint32_t i) {
      take_targets_around(r_.touched[i].a);
      take_targets_around(r_.touched[i].b);
    });
    Motion* const bodies = s_.bodies.data();
    for_each_collided([&](std::uint32_t i) {
      const Touched& c = r_.touched[i];
      TouchedState& t = r_.state[i];
      const Real delta = t.collision - t.total_normal_impulse;
      t.applied = delta;
      bodies[c.a].linear_velocity -= (bodies[c.a].inverse_mass * delta) * c.normal;
      bodies[c.b].linear_velocity += (bodies[c.b].inverse_mass * delta) * c.normal;
    });
  }

  /// 4. Inelastic clean-up around them: Gauss–Seidel passes over the contacts queued by
  /// replace_impulses, in that order, at most max_passes, until a pass changes nothing. (A
  /// contact outside the queue whose bodies this moves is not solved again: what remains is left
  /// to the next step, which treats it as inelastic.)
  void clean_up(int max_passes) {
    const Real tolerance = Real(1e-3) * std::max(threshold_, Real(1e-3));  // m/s
    Motion* const bodies = s_.bodies.data();
    bool changed = true;
    for (int pass = 0; pass < max_passes && changed; ++pass) {
      changed = false;
      for (const std::uint32_t i : r_.queue) {
        const Touched& c = r_.touched[i];
        TouchedState& t = r_.state[i];
        const Vec3 n = c.normal;
        const Real vn = n.dot(bodies[c.b].linear_velocity - bodies[c.a].linear_velocity);
        if (std::abs(t.target - vn) <= tolerance) continue;
        const Real next = std::max(t.applied + t.normal_mass * (t.target - vn), t.lower);
        const Real delta = next - t.applied;
        if (delta == 0) continue;
        changed = true;
        t.applied = next;
        bodies[c.a].linear_velocity -= (bodies[c.a].inverse_mass * delta) * n;
        bodies[c.b].linear_velocity += (bodies[c.b].inverse_mass * delta) * n;
      }
    }
  }

  /// Bookkeeping: totals and the largest impulse for events; warm starting. A contact that
  /// collided warm-starts the next step with what the clean-up added above its collision
  /// impulses (applied - lower, per substep): its support, not the impact (see the top).
  void finish() {
    for (std::uint32_t i = 0; i < r_.touched_count; ++i) {
      if (!(r_.flags[i] & (RestitutionScratch::kCleaned | RestitutionScratch::kCollided))) {
        continue;  // the pass did not change it
      }
      const TouchedState& t = r_.state[i];
      if (t.applied == 0 && t.collision < 0) continue;
      ContactBlock& c = s_.blocks[t.where / kLanes];
      const int l = static_cast<int>(t.where % kLanes);
      s_.extra[t.where / kLanes].total_normal_impulse[l] += t.applied;
      // A contact that collided has its lower bound once cleaned (every one with a moving body).
      const bool cleaned = r_.flags[i] & RestitutionScratch::kCleaned;
      const Real support = cleaned ? std::max(t.applied - t.lower, Real(0)) / substeps_ : Real(0);
      // A vector lane, not an lvalue to bind a reference to (Clang refuses): read, then write.
      const Real warm =
          t.collision >= 0 ? support : std::max(c.normal_impulse[l] + t.applied, Real(0));
      c.normal_impulse[l] = warm;
      c.max_normal_impulse[l] =
          std::max({c.max_normal_impulse[l], warm, std::max(t.collision, Real(0))});
    }
  }

 private:
  using Touched = RestitutionScratch::Touched;
  using TouchedState = RestitutionScratch::TouchedState;

  bool moves(std::uint32_t body) const { return s_.bodies[body].inverse_mass > 0; }
  Vec3 acceleration(std::uint32_t body) const {
    return body < s_.acceleration.size() ? s_.acceleration[body] : Vec3::Zero().eval();
  }

  /// Calls f with the index of each contact that collided, in lane order.
  template <class F>
  void for_each_collided(F&& f) {
    for (std::size_t w = 0; w < r_.collided.size(); ++w) {
      for (std::uint64_t bits = r_.collided[w]; bits != 0; bits &= bits - 1)
        f(static_cast<std::uint32_t>(w * 64) + static_cast<std::uint32_t>(std::countr_zero(bits)));
    }
  }

  void queue_bouncing_neighbours(std::uint32_t body) {
    if (!moves(body)) return;
    std::uint8_t* const flags = r_.flags.data();
    const std::uint32_t* const adjacent = r_.adjacent.data();
    const std::uint32_t end = r_.start[body + 1];
    for (std::uint32_t e = r_.start[body]; e < end; ++e) {
      const std::uint32_t j = adjacent[e] / 2;
      if ((flags[j] & (RestitutionScratch::kBounces | RestitutionScratch::kQueued)) !=
          RestitutionScratch::kBounces) {
        continue;
      }
      flags[j] |= RestitutionScratch::kQueued;
      r_.queue.push_back(j);
    }
  }

  /// Queues for the clean-up every touched contact of the body whose target is not yet taken,
  /// taking it now.
  void take_targets_around(std::uint32_t body) {
    if (!moves(body) || r_.targets_taken[body]) return;
    const Motion* const bodies = s_.bodies.data();
    const Touched* const touched = r_.touched.data();
    TouchedState* const state = r_.state.data();
    std::uint8_t* const flags = r_.flags.data();
    const std::uint32_t* const adjacent = r_.adjacent.data();
    const std::uint32_t end = r_.start[body + 1];
    bool all_taken = true;
    for (std::uint32_t e = r_.start[body]; e < end; ++e) {
      const std::uint32_t j = adjacent[e] / 2;
      if (flags[j] & RestitutionScratch::kTaken) continue;
      const Touched& c = touched[j];
      TouchedState& t = state[j];
      if (t.collision >= 0) {
        t.target = 0;
        t.lower = t.collision - t.total_normal_impulse;
      } else {
        t.target = c.normal.dot(bodies[c.b].linear_velocity - bodies[c.a].linear_velocity);
        t.lower = -t.total_normal_impulse;
      }
      const bool taken = !std::isnan(t.target);
      all_taken = all_taken && taken;
      flags[j] |= RestitutionScratch::kCleaned | (taken ? RestitutionScratch::kTaken : 0);
      r_.queue.push_back(j);
    }
    r_.targets_taken[body] = all_taken;  // then a walk again would change nothing
  }

  SolverScratch& s_;
  RestitutionScratch& r_;
  Real threshold_;
  Real h_;
  Real half_h_;
  Real substeps_;
};

}  // namespace

void WorldImpl::apply_restitution(Real h) {
  if (!def.enable_restitution) return;
  const Real half_h = (def.integrator == Integrator::ExplicitEuler ? Real(-0.5) : Real(0.5)) * h;
  CollisionPass pass(scratch.solver, def.restitution_threshold, h, half_h, def.substeps);
  if (!pass.any_fast_approach()) return;
  pass.gather_contacts();
  pass.replay_collisions();
  pass.replace_impulses();
  pass.clean_up(def.iterations);
  pass.finish();
}

}  // namespace ricochet::physics
