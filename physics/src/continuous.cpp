/// Continuous collision for bodies flagged fast: after positions are integrated, each fast body's
/// motion is swept against static geometry (planes, then the BVH) and other bodies (sweep and
/// prune). At the first time of impact the body
/// is moved back to touch (less linear_slop) and keeps its velocity; the next step's speculative
/// contact then stops or bounces it. So a bullet never passes through a wall, whatever its speed.

#include <algorithm>
#include <cmath>

#include "world_impl.h"

namespace ricochet::physics {

void WorldImpl::solve_continuous() {
  if (!def.enable_continuous) return;
  std::vector<std::uint32_t>& fast = fast_bodies;
  fast.clear();
  for (const std::uint32_t s : awake_list) {
    if (bodies.simulated(s) && bodies.has(s, kFlagFast) && !bodies.has(s, kFlagSensor))
      fast.push_back(s);
  }
  if (fast.empty()) return;
  time_of_impact.assign(fast.size(), Real(1));
  std::vector<std::uint8_t>& sweeping = fast_sweeping;
  sweeping.assign(fast.size(), 0);

  const auto start_of = [&](std::uint32_t s) -> const Vec3& { return start_position[s]; };
  for (std::size_t k = 0; k < fast.size(); ++k) {
    const std::uint32_t body = fast[k];
    const Real r = bodies.radius[body];
    const Vec3 o = start_of(body);
    const Vec3 d = bodies.position[body] - o;
    if (d.squaredNorm() < Real(0.25) * r * r) continue;  // speculative contacts cover short moves
    sweeping[k] = 1;
    const Filter& filter = bodies.filter[body];
    SweepHit hit;
    for (const std::uint32_t slot : statics.plane_slots()) {
      const StaticShape& plane = statics.shape(slot);
      if (collides(filter, plane.filter))
        sweep_sphere_plane(o, d, r, plane.plane_normal, plane.plane_offset, hit);
    }
    statics.query_segment(o, d, r, [&](std::uint32_t primitive) {
      if (collides(filter, statics.shape(statics.primitive(primitive).shape).filter)) {
        statics.sweep(primitive, o, d, r, hit);
      }
    });
    time_of_impact[k] = hit.t;
  }
  sweep_bodies_against_bodies();
  for (std::size_t k = 0; k < fast.size(); ++k) {
    if (time_of_impact[k] >= 1) continue;
    const std::uint32_t body = fast[k];
    const Vec3 o = start_of(body);
    const Vec3 d = bodies.position[body] - o;
    const Real length = d.norm();
    const Real t = std::max(Real(0), time_of_impact[k] - def.linear_slop / length);
    bodies.position[body] = o + d * t;
  }
}

Real WorldImpl::sort_body_move_boxes() {
  std::vector<SweptBox>& boxes = swept_boxes;
  boxes.clear();
  Real widest = 0;
  for (std::uint32_t s = 0; s < bodies.slot_count(); ++s) {
    if (!bodies.alive(s) || bodies.has(s, kFlagSensor)) continue;
    const Vec3& to = bodies.position[s];
    const Vec3& from = start_position[s];
    const Vec3 r = Vec3::Constant(bodies.radius[s]);
    boxes.push_back({from.cwiseMin(to) - r, from.cwiseMax(to) + r, s});
    widest = std::max(widest, boxes.back().hi.x() - boxes.back().lo.x());
  }
  std::sort(boxes.begin(), boxes.end(), [](const SweptBox& x, const SweptBox& y) {
    return x.lo.x() < y.lo.x() || (x.lo.x() == y.lo.x() && x.body < y.body);
  });
  return widest;
}

/// Fast bodies against every other body (sleeping ones too) by relative motion: sweep and prune
/// over the boxes around each body's whole move, along x, sorted by box start then slot so the
/// pair order is deterministic. A pair is tested when one side is a sweeping fast body; each
/// sweeping side takes the pair's time of impact.
void WorldImpl::sweep_bodies_against_bodies() {
  const std::vector<std::uint32_t>& fast = fast_bodies;
  fast_index.assign(bodies.slot_count(), kNotFast);
  for (std::uint32_t k = 0; k < fast.size(); ++k) fast_index[fast[k]] = k;
  sort_body_move_boxes();
  const std::vector<SweptBox>& boxes = swept_boxes;
  const auto sweeps = [&](std::uint32_t s) {
    return fast_index[s] != kNotFast && fast_sweeping[fast_index[s]] != 0;
  };
  for (std::size_t m = 0; m < boxes.size(); ++m) {
    const SweptBox& p = boxes[m];
    for (std::size_t n = m + 1; n < boxes.size() && boxes[n].lo.x() <= p.hi.x(); ++n) {
      const SweptBox& q = boxes[n];
      const std::uint32_t a = p.body, b = q.body;
      if (!sweeps(a) && !sweeps(b)) continue;
      if (q.lo.y() > p.hi.y() || p.lo.y() > q.hi.y() || q.lo.z() > p.hi.z() ||
          p.lo.z() > q.hi.z()) {
        continue;
      }
      if (!collides(bodies.filter[a], bodies.filter[b])) continue;
      const Vec3 o = start_position[a] - start_position[b];
      const Vec3 d =
          (bodies.position[a] - start_position[a]) - (bodies.position[b] - start_position[b]);
      SweepHit hit;
      if (!sweep_sphere_point(o, d, bodies.radius[a] + bodies.radius[b], Vec3::Zero(), hit))
        continue;
      if (sweeps(a)) time_of_impact[fast_index[a]] = std::min(time_of_impact[fast_index[a]], hit.t);
      if (sweeps(b)) time_of_impact[fast_index[b]] = std::min(time_of_impact[fast_index[b]], hit.t);
    }
  }
}

}  // namespace ricochet::physics
