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
///      the impact.
///
/// A step without a fast approach changes nothing, so resting contacts and stacks behave as
/// without restitution.

#include <algorithm>
#include <cmath>
#include <limits>

#include "world_impl.h"

namespace ricochet::physics {

namespace {

/// A contact of the step as this pass sees it.
struct ContactRef {
  ContactBlock* block;
  ContactBlockExtra* extra;
  int lane;
  std::uint32_t a() const { return block->a[lane]; }
  std::uint32_t b() const { return block->b[lane]; }
  Vec3 normal() const { return Vec3(block->nx[lane], block->ny[lane], block->nz[lane]); }
};

/// Contacts are named by where they are, block · kLanes + lane, so that the passes over all of
/// them read the blocks in order. An unused lane has restitution 0, no impulse and the dummy on
/// both sides, so every test below skips it.
ContactRef contact_ref(SolverScratch& s, std::uint32_t where) {
  return {&s.blocks[where / kLanes], &s.extra[where / kLanes], static_cast<int>(where % kLanes)};
}

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

}  // namespace

void WorldImpl::apply_restitution(Real h) {
  if (!def.enable_restitution) return;
  SolverScratch& s = scratch.solver;
  const Real threshold = def.restitution_threshold;
  const std::uint32_t total = static_cast<std::uint32_t>(s.blocks.size()) * kLanes;
  const auto bounces = [&](const ContactRef& c) {
    return c.extra->restitution[c.lane] != 0 && c.block->max_normal_impulse[c.lane] > 0;
  };
  const auto is_seed = [&](const ContactRef& c) {
    return bounces(c) && c.extra->relative_velocity[c.lane] <= -threshold;
  };
  std::uint32_t seeds = 0;
  for (std::uint32_t i = 0; i < total; ++i) seeds += is_seed(contact_ref(s, i)) ? 1 : 0;
  if (seeds == 0) return;

  const std::uint32_t body_count = static_cast<std::uint32_t>(s.bodies.size());  // with dummy
  const Real half_h = (def.integrator == Integrator::ExplicitEuler ? Real(-0.5) : Real(0.5)) * h;
  const auto acceleration = [&](std::uint32_t body) -> Vec3 {
    return body < s.acceleration.size() ? s.acceleration[body] : Vec3::Zero().eval();
  };
  const auto moves = [&](std::uint32_t body) { return s.bodies[body].inverse_mass > 0; };

  // Contacts per solver body (compressed rows); the dummy's static contacts are never needed.
  std::vector<std::uint32_t>& start = s.restitution_start;
  std::vector<std::uint32_t>& adjacent = s.restitution_adjacent;
  start.assign(body_count + 1, 0);
  for (std::uint32_t i = 0; i < total; ++i) {
    const ContactRef c = contact_ref(s, i);
    if (moves(c.a())) ++start[c.a() + 1];
    if (moves(c.b())) ++start[c.b() + 1];
  }
  for (std::uint32_t k = 0; k < body_count; ++k) start[k + 1] += start[k];
  adjacent.resize(start[body_count]);
  s.cursor.assign(start.begin(), start.end() - 1);
  for (std::uint32_t i = 0; i < total; ++i) {
    const ContactRef c = contact_ref(s, i);
    if (moves(c.a())) adjacent[s.cursor[c.a()]++] = i;
    if (moves(c.b())) adjacent[s.cursor[c.b()]++] = i;
  }
  std::vector<std::uint32_t>& queue = s.restitution_queue;
  std::vector<std::uint8_t>& queued = s.restitution_queued;
  queued.assign(total, 0);
  queue.clear();
  const auto enqueue_neighbours = [&](std::uint32_t body, auto&& wanted) {
    if (!moves(body)) return;
    for (std::uint32_t e = start[body]; e < start[body + 1]; ++e) {
      const std::uint32_t j = adjacent[e];
      if (!queued[j] && wanted(contact_ref(s, j))) {
        queued[j] = 1;
        queue.push_back(j);
      }
    }
  };

  // 1. Collision velocities.
  std::vector<Vec3>& x = s.collision_velocity;
  x.resize(body_count);
  for (std::uint32_t k = 0; k < body_count; ++k) x[k] = s.bodies[k].linear_velocity;
  for (std::uint32_t i = 0; i < total; ++i) {
    const ContactRef c = contact_ref(s, i);
    if (!bounces(c)) continue;
    const Real p = c.extra->total_normal_impulse[c.lane];
    x[c.a()] += (s.bodies[c.a()].inverse_mass * p) * c.normal();
    x[c.b()] -= (s.bodies[c.b()].inverse_mass * p) * c.normal();
  }

  // 2. Collisions, in sequence.
  std::vector<Real>& collision = s.collision_impulse;  // per contact, N·s; < 0: never collided
  collision.assign(total, Real(-1));
  for (std::uint32_t i = 0; i < total; ++i) {
    if (is_seed(contact_ref(s, i))) {
      queued[i] = 1;
      queue.push_back(i);
    }
  }
  // Every collision moves energy on or loses it, so this ends; the cap is for float rounding.
  const std::size_t max_collisions = 16 * static_cast<std::size_t>(total) + 16;
  std::size_t collisions = 0;
  for (std::size_t head = 0; head < queue.size() && collisions < max_collisions; ++head) {
    const std::uint32_t i = queue[head];
    queued[i] = 0;
    const ContactRef c = contact_ref(s, i);
    const Vec3 n = c.normal();
    const std::uint32_t a = c.a(), b = c.b();
    const Real vn = n.dot(x[b] - x[a]);
    const bool first = collision[i] < 0;
    const Real accel = n.dot(acceleration(b) - acceleration(a));
    Real v = 0;  // approach at step start
    if (first && is_seed(c)) {
      v = c.extra->relative_velocity[c.lane];
    } else if (vn <= -threshold) {
      v = vn - accel * h;
    } else {
      continue;
    }
    const Real gap = first ? std::max(c.block->separation[c.lane], Real(0)) : Real(0);
    const Real end_gap = std::max(
        c.block->separation[c.lane] + n.dot(s.delta_position[b] - s.delta_position[a]), Real(0));
    const Real target =
        departure_speed(v, accel, half_h, gap, end_gap, c.extra->restitution[c.lane]);
    const Real impulse = std::max(c.block->normal_mass[c.lane] * (target - vn), Real(0));
    collision[i] = std::max(collision[i], Real(0)) + impulse;
    ++collisions;
    if (impulse == 0) continue;
    x[a] -= (s.bodies[a].inverse_mass * impulse) * n;
    x[b] += (s.bodies[b].inverse_mass * impulse) * n;
    const auto can_collide = [&](const ContactRef& next) { return bounces(next); };
    enqueue_neighbours(a, can_collide);
    enqueue_neighbours(b, can_collide);
  }

  // 4 (targets first). Every touched contact around a body that step 3 or 4 moves is solved
  // again, towards the relative velocity it had before: a contact that collided towards not
  // approaching, with no less than its collision impulse; any other with no less than none.
  queue.clear();
  std::fill(queued.begin(), queued.end(), 0);
  std::vector<Real>& target = s.restitution_target;  // m/s, per contact; NaN: not yet taken
  std::vector<Real>& lower = s.restitution_lower;    // N·s, least impulse this pass may add
  target.assign(total, std::numeric_limits<Real>::quiet_NaN());
  lower.resize(total);
  std::vector<Real>& applied = s.restitution_applied;  // N·s, added by this pass per contact
  applied.assign(total, 0);
  const auto take_targets_around = [&](std::uint32_t body) {
    if (!moves(body)) return;
    for (std::uint32_t e = start[body]; e < start[body + 1]; ++e) {
      const std::uint32_t j = adjacent[e];
      const ContactRef c = contact_ref(s, j);
      if (!std::isnan(target[j]) || c.block->max_normal_impulse[c.lane] == 0) continue;
      const Real total_impulse = c.extra->total_normal_impulse[c.lane];
      if (collision[j] >= 0) {
        target[j] = 0;
        lower[j] = collision[j] - total_impulse;
      } else {
        target[j] =
            c.normal().dot(s.bodies[c.b()].linear_velocity - s.bodies[c.a()].linear_velocity);
        lower[j] = -total_impulse;
      }
      queued[j] = 1;
      queue.push_back(j);
    }
  };
  for (std::uint32_t i = 0; i < total; ++i) {
    if (collision[i] < 0) continue;
    const ContactRef c = contact_ref(s, i);
    take_targets_around(c.a());
    take_targets_around(c.b());
  }

  // 3. Collision impulses replace the solve's.
  for (std::uint32_t i = 0; i < total; ++i) {
    if (collision[i] < 0) continue;
    const ContactRef c = contact_ref(s, i);
    const Real delta = collision[i] - c.extra->total_normal_impulse[c.lane];
    applied[i] = delta;
    s.bodies[c.a()].linear_velocity -= (s.bodies[c.a()].inverse_mass * delta) * c.normal();
    s.bodies[c.b()].linear_velocity += (s.bodies[c.b()].inverse_mass * delta) * c.normal();
  }

  // 4. Inelastic clean-up around them, Gauss–Seidel over a first-in, first-out work list.
  // A cap on the clean-up: twice the contacts around the collisions (a wave that spreads into a
  // pile further is left to the next step, which treats what remains of it as inelastic).
  const Real tolerance = Real(1e-3) * std::max(threshold, Real(1e-3));  // m/s
  const std::size_t max_solves = queue.size();
  std::size_t solves = 0;
  for (std::size_t head = 0; head < queue.size() && solves < max_solves; ++head, ++solves) {
    const std::uint32_t i = queue[head];
    queued[i] = 0;
    const ContactRef c = contact_ref(s, i);
    const Vec3 n = c.normal();
    const std::uint32_t a = c.a(), b = c.b();
    const Real vn = n.dot(s.bodies[b].linear_velocity - s.bodies[a].linear_velocity);
    if (std::abs(target[i] - vn) <= tolerance) continue;
    const Real next =
        std::max(applied[i] + c.block->normal_mass[c.lane] * (target[i] - vn), lower[i]);
    const Real delta = next - applied[i];
    if (delta == 0) continue;
    take_targets_around(a);  // before the change: what the solve left there
    take_targets_around(b);
    applied[i] = next;
    s.bodies[a].linear_velocity -= (s.bodies[a].inverse_mass * delta) * n;
    s.bodies[b].linear_velocity += (s.bodies[b].inverse_mass * delta) * n;
    for (const std::uint32_t body : {a, b}) {
      if (!moves(body)) continue;
      for (std::uint32_t e = start[body]; e < start[body + 1]; ++e) {
        const std::uint32_t j = adjacent[e];
        if (queued[j] || j == i || std::isnan(target[j])) continue;
        queued[j] = 1;
        queue.push_back(j);
      }
    }
  }

  // Bookkeeping: totals and the largest impulse for events; warm starting. A contact that
  // collided leaves separating, so it warm-starts the next step with nothing: its collision
  // impulse carried over would have to be taken back by the next solve, which a chain does
  // only approximately.
  for (std::uint32_t i = 0; i < total; ++i) {
    if (applied[i] == 0 && collision[i] < 0) continue;
    const ContactRef c = contact_ref(s, i);
    const int l = c.lane;
    c.extra->total_normal_impulse[l] += applied[i];
    // A vector lane, not an lvalue to bind a reference to (Clang refuses): read, then write.
    const Real warm =
        collision[i] >= 0 ? Real(0) : std::max(c.block->normal_impulse[l] + applied[i], Real(0));
    c.block->normal_impulse[l] = warm;
    c.block->max_normal_impulse[l] =
        std::max({c.block->max_normal_impulse[l], warm, std::max(collision[i], Real(0))});
  }
}

}  // namespace ricochet::physics
