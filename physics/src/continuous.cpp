/// Continuous collision for bodies flagged fast: after positions are integrated, each fast body's
/// motion is swept against static geometry (planes, then the BVH) and other bodies (sweep and
/// prune). At the first time of impact the body
/// is moved back to touch (less linear_slop) and keeps its velocity; the next step's speculative
/// contact then stops or bounces it. So a bullet never passes through a wall, whatever its speed.

#include <algorithm>
#include <cmath>

#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

void WorldImpl::solve_continuous() {
  if (!def.enable_continuous) return;
  std::vector<std::uint32_t>& fast = scratch.fast_bodies;
  fast.clear();
  for (const std::uint32_t s : scratch.awake_list) {
    if (state.bodies.simulated(s) && state.bodies.has(s, kFlagFast) &&
        !state.bodies.has(s, kFlagSensor))
      fast.push_back(s);
  }
  if (fast.empty()) return;
  assign_reusing(scratch.time_of_impact, fast.size(), Real(1));
  std::vector<std::uint8_t>& sweeping = scratch.fast_sweeping;
  assign_reusing(sweeping, fast.size(), 0);

  const auto start_of = [&](std::uint32_t s) -> const Vec3& { return scratch.start_position[s]; };
  for (std::size_t k = 0; k < fast.size(); ++k) {
    const std::uint32_t body = fast[k];
    const Real r = state.bodies.radius[body];
    const Vec3 o = start_of(body);
    const Vec3 d = state.bodies.position[body] - o;
    if (d.squaredNorm() < Real(0.25) * r * r) continue;  // speculative contacts cover short moves
    sweeping[k] = 1;
    const Filter& filter = state.bodies.filter[body];
    SweepHit hit;
    for (const std::uint32_t slot : state.statics.plane_slots()) {
      const StaticShape& plane = state.statics.shape(slot);
      if (collides(filter, plane.filter))
        sweep_sphere_plane(o, d, r, plane.plane_normal, plane.plane_offset, hit);
    }
    state.statics.query_segment(o, d, r, [&](std::uint32_t primitive) {
      if (collides(filter, state.statics.shape(state.statics.primitive(primitive).shape).filter)) {
        state.statics.sweep(primitive, o, d, r, hit);
      }
    });
    scratch.time_of_impact[k] = hit.t;
  }
  sweep_bodies_against_bodies();
  for (std::size_t k = 0; k < fast.size(); ++k) {
    if (scratch.time_of_impact[k] >= 1) continue;
    const std::uint32_t body = fast[k];
    const Vec3 o = start_of(body);
    const Vec3 d = state.bodies.position[body] - o;
    const Real length = d.norm();
    const Real t = std::max(Real(0), scratch.time_of_impact[k] - def.linear_slop / length);
    state.bodies.position[body] = o + d * t;
  }
}

Real WorldImpl::sort_body_move_boxes() {
  std::vector<StepScratch::SweptBox>& boxes = scratch.swept_boxes;
  boxes.clear();
  Real widest = 0;
  for (std::uint32_t s = 0; s < state.bodies.slot_count(); ++s) {
    if (!state.bodies.alive(s) || state.bodies.has(s, kFlagSensor)) continue;
    const Vec3& to = state.bodies.position[s];
    const Vec3& from = scratch.start_position[s];
    const Vec3 r = Vec3::Constant(state.bodies.radius[s]);
    boxes.push_back({from.cwiseMin(to) - r, from.cwiseMax(to) + r, s});
    widest = std::max(widest, boxes.back().hi.x() - boxes.back().lo.x());
  }
  std::sort(boxes.begin(), boxes.end(),
            [](const StepScratch::SweptBox& x, const StepScratch::SweptBox& y) {
              return x.lo.x() < y.lo.x() || (x.lo.x() == y.lo.x() && x.body < y.body);
            });
  return widest;
}

/// Fast bodies against every other body (sleeping ones too) by relative motion: sweep and prune
/// over the boxes around each body's whole move, along x, sorted by box start then slot so the
/// pair order is deterministic. A pair is tested when one side is a sweeping fast body; each
/// sweeping side takes the pair's time of impact.
void WorldImpl::sweep_bodies_against_bodies() {
  const std::vector<std::uint32_t>& fast = scratch.fast_bodies;
  assign_reusing(scratch.fast_index, state.bodies.slot_count(), StepScratch::kNotFast);
  for (std::uint32_t k = 0; k < fast.size(); ++k) scratch.fast_index[fast[k]] = k;
  sort_body_move_boxes();
  const std::vector<StepScratch::SweptBox>& boxes = scratch.swept_boxes;
  const auto sweeps = [&](std::uint32_t s) {
    return scratch.fast_index[s] != StepScratch::kNotFast &&
           scratch.fast_sweeping[scratch.fast_index[s]] != 0;
  };
  for (std::size_t m = 0; m < boxes.size(); ++m) {
    const StepScratch::SweptBox& p = boxes[m];
    for (std::size_t n = m + 1; n < boxes.size() && boxes[n].lo.x() <= p.hi.x(); ++n) {
      const StepScratch::SweptBox& q = boxes[n];
      const std::uint32_t a = p.body, b = q.body;
      if (!sweeps(a) && !sweeps(b)) continue;
      if (q.lo.y() > p.hi.y() || p.lo.y() > q.hi.y() || q.lo.z() > p.hi.z() ||
          p.lo.z() > q.hi.z()) {
        continue;
      }
      if (!collides(state.bodies.filter[a], state.bodies.filter[b])) continue;
      const Vec3 o = scratch.start_position[a] - scratch.start_position[b];
      const Vec3 d = (state.bodies.position[a] - scratch.start_position[a]) -
                     (state.bodies.position[b] - scratch.start_position[b]);
      SweepHit hit;
      if (!sweep_sphere_point(o, d, state.bodies.radius[a] + state.bodies.radius[b], Vec3::Zero(),
                              hit))
        continue;
      if (sweeps(a))
        scratch.time_of_impact[scratch.fast_index[a]] =
            std::min(scratch.time_of_impact[scratch.fast_index[a]], hit.t);
      if (sweeps(b))
        scratch.time_of_impact[scratch.fast_index[b]] =
            std::min(scratch.time_of_impact[scratch.fast_index[b]], hit.t);
    }
  }
}

}  // namespace ricochet::physics
