/// Ray casts, sphere casts and sphere overlaps against static shapes (planes directly, boxes and
/// triangles through the BVH), bodies (through the query grid, query_grid.h) and, for lag
/// compensation, caller-supplied spheres. A ray is a sphere cast of radius 0. A cast that starts
/// inside an object does not report that object.
///
/// Every candidate is tested exactly as a scan of every slot would test it (same bounding-box
/// reject, same sweep over the whole cast), and ties go the way that scan's order sends them
/// (static shapes first, then bodies by slot), so the grid changes the cost, not the answer.
/// Closest-hit casts walk the statics' BVH nearest box first, skipping boxes beyond the closest
/// hit so far, then walk the grid only up to that hit.

#include <algorithm>

#include "world_impl.h"

namespace ricochet::physics {

namespace {

bool body_passes(const BodyStore& bodies, std::uint32_t s, const QueryFilter& filter) {
  if (!bodies.alive(s) || !filter.bodies) return false;
  if (bodies.has(s, kFlagSensor) && !filter.sensors) return false;
  if ((bodies.filter[s].layer & filter.mask) == 0) return false;
  return filter.ignore != bodies.id_of(s);
}

/// The cast o..o+d, a sphere of the given radius, and what it may hit.
struct Cast {
  const WorldImpl& world;
  const Vec3& o;
  Real radius;
  const Vec3& d;
  const QueryFilter& filter;
};

/// Calls report(target, SweepHit) for static shapes the cast touches. all: every one; otherwise
/// nearest first, and report returns the fraction past which nothing is wanted (closest hits).
template <class Report>
void cast_statics(const Cast& c, bool all, Report&& report) {
  const StaticGeometry& statics = c.world.state.statics;
  if (!c.filter.statics) return;
  Real t_max = 1;
  for (const std::uint32_t slot : statics.plane_slots()) {
    const StaticShape& plane = statics.shape(slot);
    if ((plane.filter.layer & c.filter.mask) == 0) continue;
    SweepHit hit;
    if (sweep_sphere_plane(c.o, c.d, c.radius, plane.plane_normal, plane.plane_offset, hit))
      t_max = std::min(t_max, Real(report(c.world.shape_target(slot), hit)));
  }
  const auto test = [&](std::uint32_t primitive) -> Real {
    const std::uint32_t shape = statics.primitive(primitive).shape;
    if ((statics.shape(shape).filter.layer & c.filter.mask) == 0) return t_max;
    SweepHit hit;
    if (statics.sweep(primitive, c.o, c.d, c.radius, hit))
      t_max = std::min(t_max, Real(report(c.world.shape_target(shape), hit)));
    return t_max;
  };
  if (all) {
    statics.query_segment(c.o, c.d, c.radius, test);
  } else {
    statics.query_segment_nearest(c.o, c.d, c.radius, test);
  }
}

/// Calls report(slot, SweepHit) for every body the cast touches before fraction t_end, each
/// once, stopping early when done(t) says nothing after t is wanted.
template <class Report, class Done>
void cast_bodies(const Cast& c, Real t_end, Report&& report, Done&& done) {
  if (!c.filter.bodies) return;
  const WorldImpl& w = c.world;
  const BodyStore& bodies = w.state.bodies;
  w.query_grid.update(bodies);
  w.query_stamp.resize(bodies.slot_count(), 0);
  if (++w.query_counter == 0) std::fill(w.query_stamp.begin(), w.query_stamp.end(), 0);
  const std::uint32_t stamp = ++w.query_counter;
  Aabb path = Aabb::around_sphere(c.o, c.radius);
  path.grow(Aabb::around_sphere(c.o + c.d, c.radius));
  const auto test = [&](std::uint32_t s) {
    if (w.query_stamp[s] == stamp) return;
    w.query_stamp[s] = stamp;
    if (!body_passes(bodies, s, c.filter)) return;
    if (!path.overlaps(Aabb::around_sphere(bodies.position[s], bodies.radius[s]))) return;
    SweepHit hit;
    if (sweep_sphere_point(c.o, c.d, c.radius + bodies.radius[s], bodies.position[s], hit))
      report(s, hit);
  };
  for (const std::uint32_t s : w.query_grid.large_bodies()) test(s);
  w.query_grid.visit_segment(c.o, c.d, t_end, c.radius, test, done);
}

/// The closest hit so far, with the order a full scan would give ties: statics, then bodies by
/// slot, then proxies.
struct Closest {
  bool found = false;
  SweepHit hit;
  ContactTarget target;
  int rank = 0;            ///< 0 static, 1 body, 2 proxy
  std::uint32_t slot = 0;  ///< body slot or proxy index

  void offer(const ContactTarget& t, const SweepHit& h, int r, std::uint32_t s) {
    const bool better =
        !found || h.t < hit.t || (h.t == hit.t && (r < rank || (r == rank && r > 0 && s < slot)));
    if (!better) return;
    found = true;
    hit = h;
    target = t;
    rank = r;
    slot = s;
  }
};

void cast_closest(const Cast& c, std::span<const SphereProxy> proxies, Closest& best) {
  cast_statics(c, false, [&](const ContactTarget& t, const SweepHit& h) {
    best.offer(t, h, 0, 0);
    return best.hit.t;
  });
  cast_bodies(
      c, best.found ? best.hit.t : Real(1),
      [&](std::uint32_t s, const SweepHit& h) { best.offer(c.world.body_target(s), h, 1, s); },
      [&](Real t) { return best.found && best.hit.t < t; });
  for (std::uint32_t i = 0; i < proxies.size(); ++i) {
    const SphereProxy& p = proxies[i];
    if (!is_finite(p.center) || !std::isfinite(p.radius) || p.radius <= 0) continue;
    if (!c.filter.ignore.is_null() && p.body == c.filter.ignore) continue;
    SweepHit hit;
    if (sweep_sphere_point(c.o, c.d, c.radius + p.radius, p.center, hit))
      best.offer({p.body, {}, p.user_data}, hit, 2, i);
  }
}

RayHit make_hit(const ContactTarget& target, const SweepHit& sweep, const Vec3& origin,
                const Vec3& d, Real radius) {
  RayHit hit;
  hit.target = target;
  hit.fraction = sweep.t;
  hit.distance = sweep.t * d.norm();
  hit.normal = sweep.normal;
  hit.point = origin + d * sweep.t - sweep.normal * radius;
  return hit;
}

bool valid_cast(const Vec3& origin, const Vec3& direction, Real max_distance, Real radius) {
  return is_finite(origin) && is_finite(direction) && std::isfinite(max_distance) &&
         max_distance > 0 && std::isfinite(radius) && radius >= 0 && direction.squaredNorm() > 0;
}

bool closest_hit(const WorldImpl& world, const Vec3& origin, Real radius, const Vec3& direction,
                 Real max_distance, const QueryFilter& filter, std::span<const SphereProxy> proxies,
                 RayHit& hit) {
  if (!valid_cast(origin, direction, max_distance, radius)) return false;
  const Vec3 d = direction.normalized() * max_distance;
  Closest best;
  cast_closest(Cast{world, origin, radius, d, filter}, proxies, best);
  if (best.found) hit = make_hit(best.target, best.hit, origin, d, radius);
  return best.found;
}

}  // namespace

bool World::ray_cast_closest(const Vec3& origin, const Vec3& direction, Real max_distance,
                             const QueryFilter& filter, RayHit& hit) const {
  return closest_hit(*impl_, origin, 0, direction, max_distance, filter, {}, hit);
}

bool World::sphere_cast(const Vec3& origin, Real radius, const Vec3& direction, Real max_distance,
                        const QueryFilter& filter, RayHit& hit) const {
  return closest_hit(*impl_, origin, radius, direction, max_distance, filter, {}, hit);
}

bool World::ray_cast_spheres(const Vec3& origin, const Vec3& direction, Real max_distance,
                             const QueryFilter& filter, std::span<const SphereProxy> spheres,
                             RayHit& hit) const {
  return closest_hit(*impl_, origin, 0, direction, max_distance, filter, spheres, hit);
}

bool World::sphere_cast_spheres(const Vec3& origin, Real radius, const Vec3& direction,
                                Real max_distance, const QueryFilter& filter,
                                std::span<const SphereProxy> spheres, RayHit& hit) const {
  return closest_hit(*impl_, origin, radius, direction, max_distance, filter, spheres, hit);
}

std::vector<RayHit> World::ray_cast_all(const Vec3& origin, const Vec3& direction,
                                        Real max_distance, const QueryFilter& filter) const {
  std::vector<RayHit> hits;
  if (!valid_cast(origin, direction, max_distance, 0)) return hits;
  const Vec3 d = direction.normalized() * max_distance;
  const Cast cast{*impl_, origin, 0, d, filter};
  cast_statics(cast, true, [&](const ContactTarget& target, const SweepHit& h) {
    hits.push_back(make_hit(target, h, origin, d, 0));
    return Real(1);
  });
  const std::size_t first_body = hits.size();
  cast_bodies(
      cast, 1,
      [&](std::uint32_t s, const SweepHit& h) {
        hits.push_back(make_hit(impl_->body_target(s), h, origin, d, 0));
      },
      [](Real) { return false; });
  // Bodies by slot, then everything by distance: the order a scan of every slot gives.
  std::sort(
      hits.begin() + static_cast<std::ptrdiff_t>(first_body), hits.end(),
      [](const RayHit& a, const RayHit& b) { return a.target.body.index < b.target.body.index; });
  std::stable_sort(hits.begin(), hits.end(),
                   [](const RayHit& a, const RayHit& b) { return a.fraction < b.fraction; });
  return hits;
}

std::vector<ContactTarget> World::overlap_sphere(const Vec3& center, Real radius,
                                                 const QueryFilter& filter) const {
  std::vector<ContactTarget> found;
  if (!is_finite(center) || !std::isfinite(radius) || radius < 0) return found;
  const WorldImpl& w = *impl_;
  if (filter.statics) {
    for (const std::uint32_t slot : w.state.statics.plane_slots()) {
      const StaticShape& plane = w.state.statics.shape(slot);
      if ((plane.filter.layer & filter.mask) == 0) continue;
      if (plane.plane_normal.dot(center) - plane.plane_offset < radius)
        found.push_back(w.shape_target(slot));
    }
    std::vector<std::uint32_t> shapes;
    w.state.statics.query_aabb(Aabb::around_sphere(center, radius), [&](std::uint32_t primitive) {
      const std::uint32_t shape = w.state.statics.primitive(primitive).shape;
      if ((w.state.statics.shape(shape).filter.layer & filter.mask) == 0) return;
      if (w.state.statics.closest_feature(primitive, center).distance < radius)
        shapes.push_back(shape);
    });
    std::sort(shapes.begin(), shapes.end());
    shapes.erase(std::unique(shapes.begin(), shapes.end()), shapes.end());
    for (const std::uint32_t shape : shapes) found.push_back(w.shape_target(shape));
  }
  if (!filter.bodies) return found;
  const BodyStore& bodies = w.state.bodies;
  w.query_grid.update(bodies);
  const std::size_t first_body = found.size();
  const auto test = [&](std::uint32_t s) {
    if (!body_passes(bodies, s, filter)) return;
    const Real reach = radius + bodies.radius[s];
    if ((bodies.position[s] - center).squaredNorm() < reach * reach)
      found.push_back(w.body_target(s));
  };
  for (const std::uint32_t s : w.query_grid.large_bodies()) test(s);
  w.query_grid.visit_box(Aabb::around_sphere(center, radius), test);
  // In slot order, each once (a body registered in several cells comes once per cell).
  const auto by_slot = [](const ContactTarget& a, const ContactTarget& b) {
    return a.body.index < b.body.index;
  };
  std::sort(found.begin() + static_cast<std::ptrdiff_t>(first_body), found.end(), by_slot);
  found.erase(std::unique(found.begin() + static_cast<std::ptrdiff_t>(first_body), found.end(),
                          [](const ContactTarget& a, const ContactTarget& b) {
                            return a.body.index == b.body.index;
                          }),
              found.end());
  return found;
}

}  // namespace ricochet::physics
