#include "geometry.h"

#include <algorithm>
#include <cmath>

namespace ricochet::physics {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const Real denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

namespace {

/// Smallest t in [0, 1] with |o + t·d - c| = R, for o outside the sphere.
bool first_root_sphere(const Vec3& o, const Vec3& d, const Vec3& c, Real R, Real& t) {
  const Vec3 m = o - c;
  const Real cc = m.squaredNorm() - R * R;
  if (cc <= 0) return false;  // starts inside
  const Real a = d.squaredNorm();
  const Real b = m.dot(d);
  if (b >= 0 || a <= 0) return false;  // moving away
  const Real disc = b * b - a * cc;
  if (disc < 0) return false;
  t = (-b - std::sqrt(disc)) / a;
  return t >= 0 && t <= 1;
}

bool record(SweepHit& hit, Real t, const Vec3& normal) {
  if (t >= hit.t) return false;
  hit.t = t;
  hit.normal = normal;
  return true;
}

}  // namespace

bool sweep_sphere_point(const Vec3& o, const Vec3& d, Real radius, const Vec3& c, SweepHit& hit) {
  Real t;
  if (!first_root_sphere(o, d, c, radius, t)) return false;
  const Vec3 n = o + d * t - c;
  const Real len = n.norm();
  return record(hit, t, len > 0 ? Vec3(n / len) : fallback_normal());
}

bool sweep_sphere_segment(const Vec3& o, const Vec3& d, Real radius, const Vec3& p, const Vec3& q,
                          SweepHit& hit) {
  bool found = sweep_sphere_point(o, d, radius, p, hit);
  found = sweep_sphere_point(o, d, radius, q, hit) || found;
  // Infinite cylinder around pq, accepted where the touch projects inside the segment.
  const Vec3 axis = q - p;
  const Real axis_len2 = axis.squaredNorm();
  if (axis_len2 <= 0) return found;
  const Vec3 m = o - p;
  const Vec3 m_perp = m - axis * (m.dot(axis) / axis_len2);
  const Vec3 d_perp = d - axis * (d.dot(axis) / axis_len2);
  const Real a = d_perp.squaredNorm();
  const Real b = m_perp.dot(d_perp);
  const Real cc = m_perp.squaredNorm() - radius * radius;
  if (a <= 0 || b >= 0) return found;
  if (cc <= 0) {
    const Real s = m.dot(axis) / axis_len2;
    if (s >= 0 && s <= 1) return found;  // starts inside the capsule body
  }
  const Real disc = b * b - a * cc;
  if (disc < 0) return found;
  const Real t = (-b - std::sqrt(disc)) / a;
  if (t < 0 || t > 1) return found;
  const Vec3 center = o + d * t;
  const Real s = (center - p).dot(axis) / axis_len2;
  if (s < 0 || s > 1) return found;
  Vec3 n = center - (p + axis * s);
  const Real len = n.norm();
  n = len > 0 ? Vec3(n / len) : fallback_normal();
  return record(hit, t, n) || found;
}

bool sweep_sphere_triangle(const Vec3& o, const Vec3& d, Real radius, const Vec3& a, const Vec3& b,
                           const Vec3& c, SweepHit& hit) {
  const Vec3 winding = (b - a).cross(c - a);
  const Real winding_len = winding.norm();
  bool found = false;
  if (winding_len > 0) {
    Vec3 n = winding / winding_len;
    Real side = n.dot(o - a);
    if (side < 0) {
      n = -n;
      side = -side;
    }
    const Real approach = n.dot(d);
    if (side > radius && approach < 0) {
      const Real t = (radius - side) / approach;
      if (t >= 0 && t <= 1) {
        // Touch point on the triangle's plane: inside when on the inner side of all three edges.
        const Vec3 touch = o + d * t - n * radius;
        const bool inside = (b - a).cross(touch - a).dot(winding) >= 0 &&
                            (c - b).cross(touch - b).dot(winding) >= 0 &&
                            (a - c).cross(touch - c).dot(winding) >= 0;
        if (inside) found = record(hit, t, n);
      }
    }
  }
  // The swept shape (triangle grown by the radius) is convex, so a path enters it once: a face
  // entry is the entry. A ray (radius 0) meets edges and vertices through the face test, whose
  // inside check includes the boundary; solving the degenerate edge capsules as well would
  // report rounding-magnified hits (~√ε early) at vertices.
  if (found || radius == 0) return found;
  found = sweep_sphere_segment(o, d, radius, a, b, hit) || found;
  found = sweep_sphere_segment(o, d, radius, b, c, hit) || found;
  found = sweep_sphere_segment(o, d, radius, c, a, hit) || found;
  return found;
}

bool sweep_sphere_local_box(const Vec3& o, const Vec3& d, Real radius, const Vec3& h,
                            SweepHit& hit) {
  // Reject paths that miss the box grown by the radius (a slab test), before any edge.
  Real enter = 0, leave = 1;
  for (int axis = 0; axis < 3; ++axis) {
    const Real extent = h[axis] + radius;
    if (d[axis] == 0) {
      if (std::abs(o[axis]) > extent) return false;
      continue;
    }
    Real t0 = (-extent - o[axis]) / d[axis], t1 = (extent - o[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return false;
  }
  bool found = false;
  // Faces pushed out by the radius.
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      const Real start = o[axis] * sign - (h[axis] + radius);
      const Real velocity = d[axis] * sign;
      if (start < 0 || velocity >= 0) continue;  // behind the face or moving away
      const Real t = -start / velocity;
      if (t > 1) continue;
      const Vec3 p = o + d * t;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      if (std::abs(p[u]) <= h[u] && std::abs(p[v]) <= h[v]) {
        Vec3 n = Vec3::Zero();
        n[axis] = Real(sign);
        found = record(hit, t, n) || found;
      }
    }
  }
  // The rounded box is convex, so a path enters it once: a face entry is the entry. A ray
  // meets edges and corners through the face test (its bounds include the boundary).
  if (found || radius == 0) return found;
  // Edges (with their corner spheres).
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int su = -1; su <= 1; su += 2) {
      for (int sv = -1; sv <= 1; sv += 2) {
        Vec3 p, q;
        p[axis] = -h[axis];
        q[axis] = h[axis];
        p[u] = q[u] = su * h[u];
        p[v] = q[v] = sv * h[v];
        found = sweep_sphere_segment(o, d, radius, p, q, hit) || found;
      }
    }
  }
  return found;
}

bool sweep_sphere_plane(const Vec3& o, const Vec3& d, Real radius, const Vec3& n, Real offset,
                        SweepHit& hit) {
  const Real start = n.dot(o) - offset - radius;
  const Real velocity = n.dot(d);
  if (start < 0 || velocity >= 0) return false;
  const Real t = -start / velocity;
  if (t > 1) return false;
  return record(hit, t, n);
}

bool segment_overlaps_aabb(const Vec3& o, const Vec3& d, const Aabb& box, Real& t_enter) {
  Real t0 = 0, t1 = 1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < Real(1e-30)) {
      if (o[k] < box.min[k] || o[k] > box.max[k]) return false;
      continue;
    }
    const Real inv = 1 / d[k];
    Real ta = (box.min[k] - o[k]) * inv;
    Real tb = (box.max[k] - o[k]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  t_enter = t0;
  return true;
}

}  // namespace ricochet::physics
