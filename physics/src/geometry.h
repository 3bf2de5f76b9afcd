#pragma once
/// Closest-point and swept-sphere primitives (after Ericson, Real-Time Collision Detection).
///
/// Sweeps move a sphere of radius r from o to o + d, t in [0, 1]. A sweep that starts already
/// overlapping the shape reports no hit: the discrete contact handles overlaps.

#include "math_util.h"

namespace ricochet::physics {

struct SweepHit {
  Real t = 1;                   ///< fraction of d at first touch
  Vec3 normal = Vec3::UnitY();  ///< unit, from the shape towards the sphere at touch
};

/// Closest point on triangle abc to p.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Sphere (radius r) swept against a point-sphere of radius R at c. Updates hit if earlier.
bool sweep_sphere_point(const Vec3& o, const Vec3& d, Real radius, const Vec3& c, SweepHit& hit);

/// Sphere swept against segment pq (a capsule of radius r around it, with round ends).
bool sweep_sphere_segment(const Vec3& o, const Vec3& d, Real radius, const Vec3& p, const Vec3& q,
                          SweepHit& hit);

/// Sphere swept against the two-sided triangle abc.
bool sweep_sphere_triangle(const Vec3& o, const Vec3& d, Real radius, const Vec3& a, const Vec3& b,
                           const Vec3& c, SweepHit& hit);

/// Sphere swept against an axis-aligned box centred at the origin (work in box space).
bool sweep_sphere_local_box(const Vec3& o, const Vec3& d, Real radius, const Vec3& half_extents,
                            SweepHit& hit);

/// Sphere swept against the solid half-space n·x <= offset.
bool sweep_sphere_plane(const Vec3& o, const Vec3& d, Real radius, const Vec3& n, Real offset,
                        SweepHit& hit);

/// Segment o..o+d against an AABB (slab test). Returns entry fraction in [0, 1] or false.
bool segment_overlaps_aabb(const Vec3& o, const Vec3& d, const Aabb& box, Real& t_enter);

}  // namespace ricochet::physics
