/// Shock propagation (after Guendelman, Bridson and Fedkiw 2003, in velocity form): one last pass
/// over the contacts from the ground up, in which the supporting body of each contact counts as
/// immovable. Sequential impulses move a load through a light body by a fraction ~1/ratio per
/// iteration, so a 1000 kg sphere on a 1 kg sphere sinks through it at 10 iterations; this pass
/// carries any load down to the ground in one sweep, whatever the mass ratio.
///
/// Support levels: bodies touching static geometry are level 1, their other neighbours level 2,
/// and so on (breadth-first over the contact graph); bodies with no path to the ground have no
/// level and are solved as usual. In a contact between different levels the lower body supports
/// the upper one; between equal levels both move. The pass only adds impulse (it removes approach,
/// never pulls), so it cannot add energy beyond the position correction the iterations already
/// apply. Momentum flows into the ground, as it would through a rigid stack.

#include <algorithm>
#include <limits>

#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {
constexpr std::uint32_t kNoLevel = std::numeric_limits<std::uint32_t>::max();
}

void WorldImpl::order_contacts_by_support() {
  SolverScratch& s = scratch.solver;
  const std::uint32_t body_count = static_cast<std::uint32_t>(s.bodies.size());  // with dummy
  const std::uint32_t dummy = body_count - 1;
  const std::size_t pair_count = state.pair_contacts.size();
  const std::size_t total = pair_count + state.static_contacts.size();

  // Pair-contact adjacency (compressed rows) over solver bodies.
  std::vector<std::uint32_t>& start = s.adjacency_start;
  std::vector<std::uint32_t>& neighbours = s.adjacency;
  assign_reusing(start, body_count + 1, 0);
  for (std::size_t i = 0; i < pair_count; ++i) {
    const Contact& c = state.pair_contacts[i];
    ++start[s.index_of[c.a] + 1];
    ++start[s.index_of[c.b] + 1];
  }
  for (std::uint32_t k = 0; k < body_count; ++k) start[k + 1] += start[k];
  neighbours.resize(start[body_count]);
  assign_reusing(s.cursor, start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < pair_count; ++i) {
    const std::uint32_t a = s.index_of[state.pair_contacts[i].a],
                        b = s.index_of[state.pair_contacts[i].b];
    neighbours[s.cursor[a]++] = b;
    neighbours[s.cursor[b]++] = a;
  }

  // Breadth-first levels from the bodies touching static geometry.
  std::vector<std::uint32_t>& level = s.support_level;
  assign_reusing(level, body_count, kNoLevel);
  level[dummy] = 0;
  std::vector<std::uint32_t>& queue = s.cursor;  // the fill cursors are spent: reuse the buffer
  queue.clear();
  for (const Contact& c : state.static_contacts) {
    const std::uint32_t a = s.index_of[c.a];
    if (a != dummy && level[a] == kNoLevel) {
      level[a] = 1;
      queue.push_back(a);
    }
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::uint32_t k = queue[head];
    for (std::uint32_t e = start[k]; e < start[k + 1]; ++e) {
      const std::uint32_t n = neighbours[e];
      if (n != dummy && level[n] == kNoLevel) {
        level[n] = level[k] + 1;
        queue.push_back(n);
      }
    }
  }

  // Contacts by the level of their supporting side (static contacts first), stable by index:
  // a counting sort over levels 0 .. deepest + 1 (unsupported contacts last, then skipped).
  std::uint32_t deepest = 0;
  for (const std::uint32_t k : queue) deepest = std::max(deepest, level[k]);
  const std::uint32_t unsupported = deepest + 1;
  std::vector<std::uint32_t>& key = s.support_key;
  key.resize(total);
  for (std::size_t i = 0; i < total; ++i) {
    std::uint32_t support = 0;
    if (i < pair_count) {
      support = std::min(level[s.index_of[state.pair_contacts[i].a]],
                         level[s.index_of[state.pair_contacts[i].b]]);
    }
    key[i] = std::min(support, unsupported);
  }
  std::vector<std::uint32_t>& first = s.adjacency_start;  // reused
  assign_reusing(first, unsupported + 2, 0);
  for (const std::uint32_t k : key) ++first[k + 1];
  for (std::uint32_t l = 0; l <= unsupported; ++l) first[l + 1] += first[l];
  std::vector<std::uint32_t>& order = s.support_order;
  order.resize(first[unsupported]);  // drops the unsupported contacts
  for (std::uint32_t i = 0; i < total; ++i) {
    if (key[i] < unsupported) order[first[key[i]]++] = i;
  }
}

void WorldImpl::propagate_shock(Real inverse_h, bool use_bias) {
  SolverScratch& s = scratch.solver;
  const std::vector<std::uint32_t>& level = s.support_level;
  for (const std::uint32_t i : s.support_order) {
    const std::uint32_t where = s.lane_of_contact[i];
    ContactBlock& c = s.blocks[where / kLanes];
    const int lane = static_cast<int>(where % kLanes);
    const std::uint32_t a = c.a[lane], b = c.b[lane];
    Motion& A = s.bodies[a];
    Motion& B = s.bodies[b];
    const Real ma = level[a] < level[b] ? Real(0) : A.inverse_mass;  // a supports b
    const Real mb = level[b] < level[a] ? Real(0) : B.inverse_mass;  // b supports a
    if (ma + mb == 0) continue;
    const Vec3 n(c.nx[lane], c.ny[lane], c.nz[lane]);
    const Real separation = c.separation[lane];
    Real bias = separation * inverse_h;  // speculative: may close the gap, no further
    if (separation <= 0) {
      bias = use_bias ? std::max(def.baumgarte * inverse_h *
                                     std::min(separation + def.linear_slop, Real(0)),
                                 -def.max_correction_speed)
                      : Real(0);
    }
    const Real vn = n.dot(B.linear_velocity - A.linear_velocity);
    const Real impulse = -(vn + bias) / (ma + mb);
    if (!(impulse > 0)) continue;  // adds support only, never pulls
    A.linear_velocity -= (ma * impulse) * n;
    B.linear_velocity += (mb * impulse) * n;
    c.normal_impulse[lane] += impulse;
    c.max_normal_impulse[lane] = std::max(c.max_normal_impulse[lane], c.normal_impulse[lane]);
  }
}

}  // namespace ricochet::physics
