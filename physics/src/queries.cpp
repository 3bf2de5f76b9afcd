/// Ray casts, sphere casts and sphere overlaps against static shapes (planes directly, boxes and
/// triangles through the BVH) and bodies. A ray is a sphere cast of radius 0. A cast that starts
/// inside an object does not report that object.
///
/// Bodies are tested one by one with a bounding-box reject: queries run between steps, when the
/// broadphase grid no longer matches body positions, and game scenes hold hundreds of bodies.

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

}  // namespace

/// Calls report(target, SweepHit) once per object hit (its first touch), in no particular order.
template <class Report>
void cast_sphere(const WorldImpl& world, const Vec3& origin, Real radius, const Vec3& d,
                 const QueryFilter& filter, Report&& report) {
  const StaticGeometry& statics = world.state.statics;
  if (filter.statics) {
    for (const std::uint32_t slot : statics.plane_slots()) {
      const StaticShape& plane = statics.shape(slot);
      if ((plane.filter.layer & filter.mask) == 0) continue;
      SweepHit hit;
      if (sweep_sphere_plane(origin, d, radius, plane.plane_normal, plane.plane_offset, hit)) {
        report(ContactTarget{{}, statics.id_of(slot)}, hit);
      }
    }
    statics.query_segment(origin, d, radius, [&](std::uint32_t primitive) {
      const std::uint32_t shape = statics.primitive(primitive).shape;
      if ((statics.shape(shape).filter.layer & filter.mask) == 0) return;
      SweepHit hit;
      if (statics.sweep(primitive, origin, d, radius, hit))
        report(ContactTarget{{}, statics.id_of(shape)}, hit);
    });
  }
  const BodyStore& bodies = world.state.bodies;
  Aabb path = Aabb::around_sphere(origin, radius);
  path.grow(Aabb::around_sphere(origin + d, radius));
  for (std::uint32_t s = 0; s < bodies.slot_count(); ++s) {
    if (!body_passes(bodies, s, filter)) continue;
    if (!path.overlaps(Aabb::around_sphere(bodies.position[s], bodies.radius[s]))) continue;
    SweepHit hit;
    if (sweep_sphere_point(origin, d, radius + bodies.radius[s], bodies.position[s], hit)) {
      report(ContactTarget{bodies.id_of(s), {}}, hit);
    }
  }
}

namespace {

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

}  // namespace

bool World::ray_cast_closest(const Vec3& origin, const Vec3& direction, Real max_distance,
                             const QueryFilter& filter, RayHit& hit) const {
  return sphere_cast(origin, 0, direction, max_distance, filter, hit);
}

bool World::sphere_cast(const Vec3& origin, Real radius, const Vec3& direction, Real max_distance,
                        const QueryFilter& filter, RayHit& hit) const {
  if (!valid_cast(origin, direction, max_distance, radius)) return false;
  const Vec3 d = direction.normalized() * max_distance;
  bool found = false;
  SweepHit best;
  ContactTarget best_target;
  cast_sphere(*impl_, origin, radius, d, filter,
              [&](const ContactTarget& target, const SweepHit& h) {
                if (!found || h.t < best.t) {
                  best = h;
                  best_target = target;
                  found = true;
                }
              });
  if (found) hit = make_hit(best_target, best, origin, d, radius);
  return found;
}

std::vector<RayHit> World::ray_cast_all(const Vec3& origin, const Vec3& direction,
                                        Real max_distance, const QueryFilter& filter) const {
  std::vector<RayHit> hits;
  if (!valid_cast(origin, direction, max_distance, 0)) return hits;
  const Vec3 d = direction.normalized() * max_distance;
  cast_sphere(*impl_, origin, 0, d, filter, [&](const ContactTarget& target, const SweepHit& h) {
    hits.push_back(make_hit(target, h, origin, d, 0));
  });
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
        found.push_back({{}, w.state.statics.id_of(slot)});
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
    for (const std::uint32_t shape : shapes) found.push_back({{}, w.state.statics.id_of(shape)});
  }
  for (std::uint32_t s = 0; s < w.state.bodies.slot_count(); ++s) {
    if (!body_passes(w.state.bodies, s, filter)) continue;
    const Real reach = radius + w.state.bodies.radius[s];
    if ((w.state.bodies.position[s] - center).squaredNorm() < reach * reach)
      found.push_back({w.state.bodies.id_of(s), {}});
  }
  return found;
}

}  // namespace ricochet::physics
