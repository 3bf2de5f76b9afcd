/// Projectiles (projectile.h): create, destroy, read, and the step phase that moves and sweeps
/// them. Per step, after the bodies have moved:
///
///   move each projectile ballistically → sweep it against static shapes (planes, then the BVH)
///   → against bodies by relative motion (sweep and prune over boxes around each whole move)
///   → the earliest touch wins: record a hit event and remove the projectile; otherwise advance
///
/// Bodies' moves are taken from their start and end positions this step, so a projectile and a
/// running player are tested along both paths, not against where the player ended.

#include <algorithm>
#include <cmath>

#include "show.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

std::string validate_projectile(const ProjectileDef& d, Real max_speed) {
  if (!is_finite(d.position)) return "position must be finite, got " + show(d.position);
  if (!is_finite(d.velocity)) return "velocity must be finite, got " + show(d.velocity);
  if (d.velocity.norm() > max_speed) {
    return "speed must be at most WorldDef::max_linear_speed = " + show(max_speed) + " m/s, got " +
           show(d.velocity.norm());
  }
  if (!std::isfinite(d.radius) || d.radius < 0)
    return "radius must be >= 0 m, got " + show(d.radius);
  if (!std::isfinite(d.gravity_scale))
    return "gravity_scale must be finite, got " + show(d.gravity_scale);
  return {};
}

}  // namespace

Result<ProjectileId> World::create_projectile(const ProjectileDef& def) {
  WorldImpl& w = *impl_;
  const std::string problem = validate_projectile(def, w.def.max_linear_speed);
  if (!problem.empty()) return Error{ErrorCode::InvalidArgument, "ProjectileDef: " + problem};
  ProjectileStore& p = w.state.projectiles;
  if (p.slots.full(w.def.max_projectiles)) {
    return Error{ErrorCode::CapacityExceeded,
                 "create_projectile: world holds max_projectiles = " + show(w.def.max_projectiles) +
                     "; raise WorldDef::max_projectiles"};
  }
  return p.id_of(p.create(def));
}

Status World::destroy_projectile(ProjectileId id) {
  if (!impl_->state.projectiles.valid(id))
    return Error{ErrorCode::InvalidHandle, "destroy_projectile: stale or null projectile handle"};
  impl_->state.projectiles.destroy(id.index);
  return {};
}

bool World::is_valid(ProjectileId id) const {
  return impl_->state.projectiles.valid(id);
}

Result<ProjectileState> World::projectile_state(ProjectileId id) const {
  const ProjectileStore& p = impl_->state.projectiles;
  if (!p.valid(id))
    return Error{ErrorCode::InvalidHandle, "projectile_state: stale or null projectile handle"};
  return ProjectileState{p.position[id.index], p.velocity[id.index], p.user_data[id.index]};
}

std::uint32_t World::projectile_count() const {
  return impl_->state.projectiles.slots.alive_count;
}

std::span<const ProjectileHitEvent> World::projectile_hit_events() const {
  return impl_->events.projectile_hits;
}

void WorldImpl::step_projectiles() {
  ProjectileStore& p = state.projectiles;
  std::vector<StepScratch::ProjectileSweep>& sweeps = scratch.projectile_sweeps;
  sweeps.clear();
  if (p.slots.alive_count == 0) return;
  const Real h = scratch.dt;
  for (std::uint32_t s = 0; s < p.slot_count(); ++s) {
    if (!p.alive(s)) continue;
    const Vec3 a = state.gravity * p.gravity_scale[s];
    StepScratch::ProjectileSweep sweep;
    sweep.slot = s;
    sweep.from = p.position[s];
    sweep.move = p.velocity[s] * h + a * (Real(0.5) * h * h);
    if (!is_finite(sweep.from + sweep.move) || !is_finite(p.velocity[s] + a * h)) {
      p.destroy(s);  // flown out of the finite range (an absurd gravity scale): gone
      continue;
    }
    sweeps.push_back(sweep);
  }
  sweep_projectiles_against_statics();
  sweep_projectiles_against_bodies();
  for (const StepScratch::ProjectileSweep& sweep : sweeps) {
    const std::uint32_t s = sweep.slot;
    const Vec3 a = state.gravity * p.gravity_scale[s];
    if (sweep.hit.t >= 1) {
      p.position[s] = sweep.from + sweep.move;
      p.velocity[s] += a * h;
      // Falling speeds up without bound; the same limit as bodies keeps it within what a save
      // image accepts.
      const Real speed2 = p.velocity[s].squaredNorm();
      if (speed2 > def.max_linear_speed * def.max_linear_speed)
        p.velocity[s] *= def.max_linear_speed / std::sqrt(speed2);
      continue;
    }
    const Real t = sweep.hit.t;
    ProjectileHitEvent e;
    e.projectile = p.id_of(s);
    e.target = sweep.target;
    e.normal = sweep.hit.normal;
    e.point = sweep.from + sweep.move * t - e.normal * p.radius[s];
    e.velocity = p.velocity[s] + a * (h * t);
    e.time = h * t;
    e.user_data = p.user_data[s];
    events.projectile_hits.push_back(e);
    p.destroy(s);
  }
}

void WorldImpl::sweep_projectiles_against_statics() {
  const ProjectileStore& p = state.projectiles;
  for (StepScratch::ProjectileSweep& sweep : scratch.projectile_sweeps) {
    const Filter& filter = p.filter[sweep.slot];
    const Real r = p.radius[sweep.slot];
    const auto keep = [&](std::uint32_t shape, const SweepHit& hit) {
      sweep.hit = hit;
      sweep.target = shape_target(shape);
    };
    for (const std::uint32_t slot : state.statics.plane_slots()) {
      const StaticShape& plane = state.statics.shape(slot);
      SweepHit hit = sweep.hit;
      if (collides(filter, plane.filter) &&
          sweep_sphere_plane(sweep.from, sweep.move, r, plane.plane_normal, plane.plane_offset,
                             hit)) {
        keep(slot, hit);
      }
    }
    state.statics.query_segment(sweep.from, sweep.move, r, [&](std::uint32_t primitive) {
      const std::uint32_t shape = state.statics.primitive(primitive).shape;
      SweepHit hit = sweep.hit;
      if (collides(filter, state.statics.shape(shape).filter) &&
          state.statics.sweep(primitive, sweep.from, sweep.move, r, hit)) {
        keep(shape, hit);
      }
    });
  }
}

/// Boxes around every body's move this step (sensors excluded), sorted along x by start then
/// slot; each projectile's box looks up the bodies whose x range can reach it by binary search
/// (a body box is at most the widest one wide). The order of tests is fixed, so ties resolve the
/// same way on every run.
void WorldImpl::sweep_projectiles_against_bodies() {
  const ProjectileStore& p = state.projectiles;
  const Real widest = sort_body_move_boxes();
  const std::vector<StepScratch::SweptBox>& boxes = scratch.swept_boxes;
  if (boxes.empty()) return;
  for (StepScratch::ProjectileSweep& sweep : scratch.projectile_sweeps) {
    const Vec3 to = sweep.from + sweep.move;
    const Real radius = p.radius[sweep.slot];
    const Vec3 lo = sweep.from.cwiseMin(to) - Vec3::Constant(radius);
    const Vec3 hi = sweep.from.cwiseMax(to) + Vec3::Constant(radius);
    const auto first =
        std::lower_bound(boxes.begin(), boxes.end(), lo.x() - widest,
                         [](const StepScratch::SweptBox& box, Real x) { return box.lo.x() < x; });
    for (auto it = first; it != boxes.end() && it->lo.x() <= hi.x(); ++it) {
      const StepScratch::SweptBox& b = *it;
      if (b.hi.x() < lo.x() || b.lo.y() > hi.y() || lo.y() > b.hi.y() || b.lo.z() > hi.z() ||
          lo.z() > b.hi.z()) {
        continue;
      }
      const std::uint32_t body = b.body;
      const BodyId ignore = p.ignore[sweep.slot];
      if (ignore == state.bodies.id_of(body)) continue;
      if (!collides(p.filter[sweep.slot], state.bodies.filter[body])) continue;
      // In the body's frame: the projectile starts at from - start and moves by the difference
      // of the two moves; the body is a point inflated by both radii.
      const Vec3 body_move = state.bodies.position[body] - scratch.start_position[body];
      SweepHit hit = sweep.hit;
      if (sweep_sphere_point(sweep.from - scratch.start_position[body], sweep.move - body_move,
                             radius + state.bodies.radius[body], Vec3::Zero(), hit)) {
        sweep.hit = hit;
        sweep.target = body_target(body);
      }
    }
  }
}

}  // namespace ricochet::physics
