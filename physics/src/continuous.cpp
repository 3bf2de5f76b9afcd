/// Continuous collision for bodies flagged fast: after positions are integrated, each fast body's
/// motion is swept against static geometry and other bodies. At the first time of impact the body
/// is moved back to touch (less linear_slop) and keeps its velocity; the next step's speculative
/// contact then stops or bounces it. So a bullet never passes through a wall, whatever its speed.

#include <algorithm>
#include <chrono>
#include <cmath>

#include "world_impl.h"

namespace ricochet::physics {

namespace {

/// Visits every grid cell the segment from `from` to `to` passes through (3-D DDA), in order.
template <class Visit>
void walk_cells(const BodyGrid& grid, const Vec3& from, const Vec3& to, Visit&& visit) {
  std::int32_t cell[3], last[3], step[3];
  Real t_max[3], t_delta[3];
  const Vec3 d = to - from;
  for (int k = 0; k < 3; ++k) {
    cell[k] = grid.coordinate(from[k]);
    last[k] = grid.coordinate(to[k]);
    step[k] = d[k] > 0 ? 1 : (d[k] < 0 ? -1 : 0);
    if (step[k] == 0) {
      t_max[k] = t_delta[k] = std::numeric_limits<Real>::max();
    } else {
      const Real boundary = (static_cast<Real>(cell[k]) + (step[k] > 0 ? 1 : 0)) * grid.cell_size;
      t_max[k] = (boundary - from[k]) / d[k];
      t_delta[k] = grid.cell_size / std::abs(d[k]);
    }
  }
  // Bounded: a segment crosses at most |Δcell| boundaries per axis.
  std::int64_t budget = 3;
  for (int k = 0; k < 3; ++k) budget += std::abs(static_cast<std::int64_t>(last[k]) - cell[k]);
  budget = std::min<std::int64_t>(budget, 1 << 16);
  while (budget-- > 0) {
    visit(cell[0], cell[1], cell[2]);
    if (cell[0] == last[0] && cell[1] == last[1] && cell[2] == last[2]) return;
    int axis = 0;
    if (t_max[1] < t_max[axis]) axis = 1;
    if (t_max[2] < t_max[axis]) axis = 2;
    if (t_max[axis] > 1) return;
    cell[axis] += step[axis];
    t_max[axis] += t_delta[axis];
  }
}

}  // namespace

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
  ccd_stamp.resize(bodies.slot_count(), 0);

  const auto start_of = [&](std::uint32_t s) -> const Vec3& { return start_position[s]; };
  for (std::size_t k = 0; k < fast.size(); ++k) {
    const std::uint32_t body = fast[k];
    const Real r = bodies.radius[body];
    const Vec3 o = start_of(body);
    const Vec3 d = bodies.position[body] - o;
    if (d.squaredNorm() < Real(0.25) * r * r) continue;  // speculative contacts cover short moves
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
    // Other bodies near the path: the grid (built at step start) holds their start cells; any body
    // within reach of the path has its centre in a neighbour of a cell the path crosses.
    ++ccd_stamp_counter;
    if (!grid.entries.empty()) {
      walk_cells(grid, o, o + d, [&](std::int32_t x, std::int32_t y, std::int32_t z) {
        for (std::int32_t dx = -1; dx <= 1; ++dx)
          for (std::int32_t dy = -1; dy <= 1; ++dy)
            for (std::int32_t dz = -1; dz <= 1; ++dz)
              grid.visit_cell(x + dx, y + dy, z + dz, [&](const BodyGrid::Entry& entry) {
                const std::uint32_t other = entry.body;
                if (other == body || ccd_stamp[other] == ccd_stamp_counter) return;
                ccd_stamp[other] = ccd_stamp_counter;
                if (bodies.has(other, kFlagSensor) || bodies.has(other, kFlagFast)) return;
                if (!collides(filter, bodies.filter[other])) return;
                const Vec3 other_start = start_of(other);
                const Vec3 relative_d = d - (bodies.position[other] - other_start);
                sweep_sphere_point(o - other_start, relative_d, r + bodies.radius[other],
                                   Vec3::Zero(), hit);
              });
      });
    }
    time_of_impact[k] = hit.t;
  }
  // Fast against fast: relative motion, both stop at the shared time of impact.
  for (std::size_t i = 0; i < fast.size(); ++i) {
    for (std::size_t j = i + 1; j < fast.size(); ++j) {
      const std::uint32_t a = fast[i], b = fast[j];
      if (!collides(bodies.filter[a], bodies.filter[b])) continue;
      const Vec3 o = start_of(a) - start_of(b);
      const Vec3 d = (bodies.position[a] - start_of(a)) - (bodies.position[b] - start_of(b));
      const Real reach = bodies.radius[a] + bodies.radius[b];
      // Quick reject: closest approach of the relative segment to the origin.
      const Real closest2 = closest_point_on_segment(Vec3::Zero(), o, o + d).squaredNorm();
      if (closest2 > reach * reach) continue;
      SweepHit hit;
      if (sweep_sphere_point(o, d, reach, Vec3::Zero(), hit)) {
        time_of_impact[i] = std::min(time_of_impact[i], hit.t);
        time_of_impact[j] = std::min(time_of_impact[j], hit.t);
      }
    }
  }
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

}  // namespace ricochet::physics
