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
/// without restitution. The pass costs one read of every contact lane to find the fast
/// approaches and, when there are some, one more to list each body's touched contacts; all else
/// is proportional to the impact region (the contacts queued and the bodies they move).

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
  /// Can bounce: e > 0 and touched this step. An unused lane has restitution 0 and no impulse.
  bool bounces() const {
    return extra->restitution[lane] != 0 && block->max_normal_impulse[lane] > 0;
  }
};

ContactRef contact_ref(SolverScratch& s, std::uint32_t where) {
  return {&s.blocks[where / kLanes], &s.extra[where / kLanes], static_cast<int>(where % kLanes)};
}

constexpr std::uint32_t kNone = ~0u;

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

/// One step's collision pass over the impact region (steps 1 to 4 above).
class CollisionPass {
 public:
  CollisionPass(SolverScratch& s, Real threshold, Real h, Real half_h)
      : s_(s), r_(s.restitution), threshold_(threshold), h_(h), half_h_(half_h) {}

  /// Queues the contacts that approached faster than the threshold (in lane order); false if
  /// there are none.
  bool queue_fast_approaches() {
    r_.queue.clear();
    for (std::size_t k = 0; k < s_.blocks.size(); ++k) {
      const ContactBlock& c = s_.blocks[k];
      const ContactBlockExtra& e = s_.extra[k];
      for (int l = 0; l < kLanes; ++l) {
        if (e.relative_velocity[l] <= -threshold_ && e.restitution[l] != 0 &&
            c.max_normal_impulse[l] > 0) {
          r_.queue.push_back(static_cast<std::uint32_t>(k) * kLanes +
                             static_cast<std::uint32_t>(l));
        }
      }
    }
    return !r_.queue.empty();
  }

  /// Lists every body's touched contacts in lane order (the only ones any step below reads),
  /// and marks the queued contacts.
  void link_contacts() {
    const std::uint32_t total = static_cast<std::uint32_t>(s_.blocks.size()) * kLanes;
    r_.first.assign(s_.bodies.size(), kNone);
    r_.next.resize(2 * static_cast<std::size_t>(total));
    r_.record_of.resize(total, kNone);
    r_.velocity_of.resize(s_.bodies.size(), kNone);
    for (std::uint32_t where = total; where-- > 0;) {  // backwards: each list comes out in order
      const ContactBlock& c = s_.blocks[where / kLanes];
      const int l = static_cast<int>(where % kLanes);
      if (c.max_normal_impulse[l] == 0) continue;
      r_.next[2 * where] = r_.first[c.a[l]];
      r_.first[c.a[l]] = 2 * where;
      r_.next[2 * where + 1] = r_.first[c.b[l]];
      r_.first[c.b[l]] = 2 * where + 1;
    }
    for (const std::uint32_t where : r_.queue) record(where).queued = true;
  }

  /// 1, 2. Collisions in sequence, first in, first out.
  void replay_collisions() {
    r_.collided.clear();
    const std::size_t total = s_.blocks.size() * kLanes;
    // Every collision moves energy on or loses it, so this ends; the cap is for float rounding.
    const std::size_t max_collisions = 16 * total + 16;
    std::size_t collisions = 0;
    for (std::size_t head = 0; head < r_.queue.size() && collisions < max_collisions; ++head) {
      const std::uint32_t i = r_.queue[head];
      const std::uint32_t record_index = r_.record_of[i];
      r_.records[record_index].queued = false;
      const ContactRef c = contact_ref(s_, i);
      const Vec3 n = c.normal();
      const std::uint32_t a = c.a(), b = c.b();
      const std::uint32_t xa = collision_velocity(a), xb = collision_velocity(b);
      const Real vn = n.dot(r_.velocity[xb] - r_.velocity[xa]);
      const Real collision = r_.records[record_index].collision;
      const bool first = collision < 0;
      const Real accel = n.dot(acceleration(b) - acceleration(a));
      Real v = 0;  // approach at step start
      if (first && c.bounces() && c.extra->relative_velocity[c.lane] <= -threshold_) {
        v = c.extra->relative_velocity[c.lane];
      } else if (vn <= -threshold_) {
        v = vn - accel * h_;
      } else {
        continue;
      }
      const Real gap = first ? std::max(c.block->separation[c.lane], Real(0)) : Real(0);
      const Real end_gap =
          std::max(c.block->separation[c.lane] + n.dot(s_.delta_position[b] - s_.delta_position[a]),
                   Real(0));
      const Real target =
          departure_speed(v, accel, half_h_, gap, end_gap, c.extra->restitution[c.lane]);
      const Real impulse = std::max(c.block->normal_mass[c.lane] * (target - vn), Real(0));
      r_.records[record_index].collision = std::max(collision, Real(0)) + impulse;
      if (first) r_.collided.push_back(i);
      ++collisions;
      if (impulse == 0) continue;
      r_.velocity[xa] -= (s_.bodies[a].inverse_mass * impulse) * n;
      r_.velocity[xb] += (s_.bodies[b].inverse_mass * impulse) * n;
      queue_bouncing_neighbours(a);
      queue_bouncing_neighbours(b);
    }
    std::sort(r_.collided.begin(), r_.collided.end());
  }

  /// 4 (targets first), then 3. Every touched contact around a body that step 3 or 4 moves is
  /// solved again, towards the relative velocity it had before: a contact that collided towards
  /// not approaching, with no less than its collision impulse; any other with no less than none.
  void replace_impulses() {
    r_.queue.clear();
    for (Record& record : r_.records) record.queued = false;
    for (const std::uint32_t i : r_.collided) {
      const ContactRef c = contact_ref(s_, i);
      take_targets_around(c.a());
      take_targets_around(c.b());
    }
    for (const std::uint32_t i : r_.collided) {
      const ContactRef c = contact_ref(s_, i);
      Record& record = r_.records[r_.record_of[i]];
      const Real delta = record.collision - c.extra->total_normal_impulse[c.lane];
      record.applied = delta;
      s_.bodies[c.a()].linear_velocity -= (s_.bodies[c.a()].inverse_mass * delta) * c.normal();
      s_.bodies[c.b()].linear_velocity += (s_.bodies[c.b()].inverse_mass * delta) * c.normal();
    }
  }

  /// 4. Inelastic clean-up around them, Gauss–Seidel over a first-in, first-out work list.
  /// A cap on the clean-up: twice the contacts around the collisions (a wave that spreads into a
  /// pile further is left to the next step, which treats what remains of it as inelastic).
  void clean_up() {
    const Real tolerance = Real(1e-3) * std::max(threshold_, Real(1e-3));  // m/s
    const std::size_t max_solves = r_.queue.size();
    std::size_t solves = 0;
    for (std::size_t head = 0; head < r_.queue.size() && solves < max_solves; ++head, ++solves) {
      const std::uint32_t i = r_.queue[head];
      r_.records[r_.record_of[i]].queued = false;
      const ContactRef c = contact_ref(s_, i);
      const Vec3 n = c.normal();
      const std::uint32_t a = c.a(), b = c.b();
      const Real vn = n.dot(s_.bodies[b].linear_velocity - s_.bodies[a].linear_velocity);
      const Record before = r_.records[r_.record_of[i]];
      if (std::abs(before.target - vn) <= tolerance) continue;
      const Real next = std::max(
          before.applied + c.block->normal_mass[c.lane] * (before.target - vn), before.lower);
      const Real delta = next - before.applied;
      if (delta == 0) continue;
      take_targets_around(a);  // before the change: what the solve left there
      take_targets_around(b);
      r_.records[r_.record_of[i]].applied = next;
      s_.bodies[a].linear_velocity -= (s_.bodies[a].inverse_mass * delta) * n;
      s_.bodies[b].linear_velocity += (s_.bodies[b].inverse_mass * delta) * n;
      for (const std::uint32_t body : {a, b}) {
        if (!moves(body)) continue;
        for (std::uint32_t e = r_.first[body]; e != kNone; e = r_.next[e]) {
          const std::uint32_t j = e / 2;
          const std::uint32_t index = r_.record_of[j];
          if (index == kNone || j == i) continue;  // no record: no target taken
          Record& neighbour = r_.records[index];
          if (neighbour.queued || std::isnan(neighbour.target)) continue;
          neighbour.queued = true;
          r_.queue.push_back(j);
        }
      }
    }
  }

  /// Bookkeeping: totals and the largest impulse for events; warm starting. A contact that
  /// collided leaves separating, so it warm-starts the next step with nothing: its collision
  /// impulse carried over would have to be taken back by the next solve, which a chain does
  /// only approximately. Then every entry of the region's maps is cleared for the next step.
  void finish() {
    for (const Record& record : r_.records) {
      r_.record_of[record.where] = kNone;
      if (record.applied == 0 && record.collision < 0) continue;
      const ContactRef c = contact_ref(s_, record.where);
      const int l = c.lane;
      c.extra->total_normal_impulse[l] += record.applied;
      Real& warm = c.block->normal_impulse[l];
      warm = record.collision >= 0 ? Real(0) : std::max(warm + record.applied, Real(0));
      c.block->max_normal_impulse[l] =
          std::max({c.block->max_normal_impulse[l], warm, std::max(record.collision, Real(0))});
    }
    r_.records.clear();
    for (const std::uint32_t body : r_.velocity_body) r_.velocity_of[body] = kNone;
    r_.velocity_body.clear();
    r_.velocity.clear();
  }

 private:
  using Record = RestitutionScratch::Record;

  bool moves(std::uint32_t body) const { return s_.bodies[body].inverse_mass > 0; }
  Vec3 acceleration(std::uint32_t body) const {
    return body < s_.acceleration.size() ? s_.acceleration[body] : Vec3::Zero().eval();
  }

  /// The contact's record, made on first use.
  Record& record(std::uint32_t where) {
    std::uint32_t& index = r_.record_of[where];
    if (index == kNone) {
      index = static_cast<std::uint32_t>(r_.records.size());
      r_.records.push_back(
          {where, false, Real(-1), std::numeric_limits<Real>::quiet_NaN(), Real(0), Real(0)});
    }
    return r_.records[index];
  }

  /// Index of the body's collision velocity, made on first use (step 1): its velocity without
  /// the step's normal impulses of the contacts that can bounce. A body that does not move
  /// keeps its velocity (its impulses are multiplied by an inverse mass of 0).
  std::uint32_t collision_velocity(std::uint32_t body) {
    std::uint32_t& index = r_.velocity_of[body];
    if (index != kNone) return index;
    index = static_cast<std::uint32_t>(r_.velocity.size());
    Vec3 x = s_.bodies[body].linear_velocity;
    if (moves(body)) {
      const Real inverse_mass = s_.bodies[body].inverse_mass;
      for (std::uint32_t e = r_.first[body]; e != kNone; e = r_.next[e]) {
        const ContactRef c = contact_ref(s_, e / 2);
        if (!c.bounces()) continue;
        const Real p = c.extra->total_normal_impulse[c.lane];
        if (e % 2 == 0) {
          x += (inverse_mass * p) * c.normal();
        } else {
          x -= (inverse_mass * p) * c.normal();
        }
      }
    }
    r_.velocity.push_back(x);
    r_.velocity_body.push_back(body);
    return index;
  }

  void queue_bouncing_neighbours(std::uint32_t body) {
    if (!moves(body)) return;
    for (std::uint32_t e = r_.first[body]; e != kNone; e = r_.next[e]) {
      const std::uint32_t j = e / 2;
      if (!contact_ref(s_, j).bounces()) continue;
      Record& next = record(j);
      if (next.queued) continue;
      next.queued = true;
      r_.queue.push_back(j);
    }
  }

  void take_targets_around(std::uint32_t body) {
    if (!moves(body)) return;
    for (std::uint32_t e = r_.first[body]; e != kNone; e = r_.next[e]) {
      const std::uint32_t j = e / 2;
      const std::uint32_t index = r_.record_of[j];
      if (index != kNone && !std::isnan(r_.records[index].target)) continue;
      const ContactRef c = contact_ref(s_, j);  // touched: listed only if max impulse != 0
      Record& record = this->record(j);
      const Real total_impulse = c.extra->total_normal_impulse[c.lane];
      if (record.collision >= 0) {
        record.target = 0;
        record.lower = record.collision - total_impulse;
      } else {
        record.target =
            c.normal().dot(s_.bodies[c.b()].linear_velocity - s_.bodies[c.a()].linear_velocity);
        record.lower = -total_impulse;
      }
      record.queued = true;
      r_.queue.push_back(j);
    }
  }

  SolverScratch& s_;
  RestitutionScratch& r_;
  Real threshold_;
  Real h_;
  Real half_h_;
};

}  // namespace

void WorldImpl::apply_restitution(Real h) {
  if (!def.enable_restitution) return;
  const Real half_h = (def.integrator == Integrator::ExplicitEuler ? Real(-0.5) : Real(0.5)) * h;
  CollisionPass pass(scratch.solver, def.restitution_threshold, h, half_h);
  if (!pass.queue_fast_approaches()) return;
  pass.link_contacts();
  pass.replay_collisions();
  pass.replace_impulses();
  pass.clean_up();
  pass.finish();
}

}  // namespace ricochet::physics
