#pragma once
/// Static shapes (planes, oriented boxes, triangle meshes) and the bounding volume hierarchy that
/// holds every box and triangle. Planes are infinite and kept in their own list.

#include <cstdint>
#include <vector>

#include "geometry.h"
#include "ricochet/physics/shapes.h"
#include "slot_pool.h"

namespace ricochet::physics {

struct StaticShape {
  ShapeType type = ShapeType::Plane;
  Material material;
  Filter filter;
  // Plane: solid below normal·x = offset.
  Vec3 plane_normal = Vec3::UnitY();
  Real plane_offset = 0;
  // Box.
  Vec3 box_center = Vec3::Zero();
  Quat box_orientation = Quat::Identity();
  Mat3 box_rotation = Mat3::Identity();  ///< local to world
  Vec3 box_half_extents = Vec3::Ones();
  // Mesh.
  std::vector<Vec3> vertices;
  std::vector<std::uint32_t> indices;
};

/// One box or one triangle in the hierarchy.
struct StaticPrimitive {
  std::uint32_t shape;  ///< slot in StaticGeometry::shapes
  std::uint32_t index;  ///< triangle index within the mesh, 0 for a box
};

/// Closest feature of a primitive to a point.
struct ClosestFeature {
  Vec3 point;     ///< on the primitive's surface
  Vec3 normal;    ///< unit, from the primitive towards the query point
  Real distance;  ///< signed: negative when the point is inside a box
  bool on_face;   ///< triangles: the closest point is inside the face, not on an edge or vertex
};

class StaticGeometry {
 public:
  std::uint32_t add(StaticShape shape);
  void remove(std::uint32_t slot);
  bool valid(ShapeId id) const { return slots_.valid(id); }
  ShapeId id_of(std::uint32_t slot) const { return slots_.id_of<ShapeTag>(slot); }
  bool alive(std::uint32_t slot) const { return slots_.alive(slot); }
  const SlotPool& slots() const { return slots_; }
  const StaticShape& shape(std::uint32_t slot) const { return shapes_[slot]; }
  const std::vector<StaticShape>& shapes() const { return shapes_; }
  const std::vector<std::uint32_t>& plane_slots() const { return plane_slots_; }
  std::uint32_t count() const { return slots_.alive_count; }

  /// Calls visit(primitive_index) for every primitive whose box overlaps `box`.
  template <class Visit>
  void query_aabb(const Aabb& box, Visit&& visit) const;
  /// Calls visit(primitive_index) for every primitive whose box, grown by `inflate`, the segment
  /// o..o+d touches.
  template <class Visit>
  void query_segment(const Vec3& o, const Vec3& d, Real inflate, Visit&& visit) const;
  /// As query_segment for a closest-hit cast, nearer boxes first: visit(primitive_index) returns
  /// the fraction of d past which nothing is wanted any more (the closest hit so far, or 1), and
  /// boxes the segment enters after it are skipped.
  template <class Visit>
  void query_segment_nearest(const Vec3& o, const Vec3& d, Real inflate, Visit&& visit) const;

  const StaticPrimitive& primitive(std::uint32_t i) const { return primitives_[i]; }
  ClosestFeature closest_feature(std::uint32_t primitive, const Vec3& point) const;
  bool sweep(std::uint32_t primitive, const Vec3& o, const Vec3& d, Real radius,
             SweepHit& hit) const;
  /// Triangle corners of a mesh primitive.
  void triangle(const StaticPrimitive& p, Vec3& a, Vec3& b, Vec3& c) const;

  /// Replaces everything (restore_state; already validated); rebuilds lists and the hierarchy.
  void assign(SlotPool slots, std::vector<StaticShape> shapes);

 private:
  struct Node {
    Aabb box;
    std::uint32_t first = 0;  ///< leaf: first primitive; inner: left child (right = first + 1)
    std::uint32_t count = 0;  ///< primitives in a leaf, 0 for an inner node
  };
  Aabb primitive_box(const StaticPrimitive& p) const;
  void build_node(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                  std::vector<Aabb>& boxes, std::vector<Vec3>& centers);
  /// Plane list, primitive list and hierarchy, after every add, remove or assign.
  void rebuild_lists();
  void rebuild_tree();

  SlotPool slots_;
  std::vector<StaticShape> shapes_;  ///< per slot; a dead slot's is default
  std::vector<std::uint32_t> plane_slots_;
  std::vector<StaticPrimitive> primitives_;
  std::vector<Aabb> primitive_boxes_;  ///< per primitive, in primitives_' order
  std::vector<Node> nodes_;
};

template <class Visit>
void StaticGeometry::query_aabb(const Aabb& box, Visit&& visit) const {
  if (nodes_.empty()) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(box)) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) visit(i);
    } else if (top + 2 <= 64) {
      stack[top++] = node.first + 1;
      stack[top++] = node.first;
    }
  }
}

template <class Visit>
void StaticGeometry::query_segment(const Vec3& o, const Vec3& d, Real inflate,
                                   Visit&& visit) const {
  if (nodes_.empty()) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  const Vec3 grow = Vec3::Constant(inflate);
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    Real t_enter;
    if (!segment_overlaps_aabb(o, d, Aabb{node.box.min - grow, node.box.max + grow}, t_enter))
      continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) visit(i);
    } else if (top + 2 <= 64) {
      stack[top++] = node.first + 1;
      stack[top++] = node.first;
    }
  }
}

template <class Visit>
void StaticGeometry::query_segment_nearest(const Vec3& o, const Vec3& d, Real inflate,
                                           Visit&& visit) const {
  if (nodes_.empty()) return;
  struct Pending {
    std::uint32_t node;
    Real t_enter;
  };
  Pending stack[64];
  int top = 0;
  // The slab test of segment_overlaps_aabb with the division hoisted out of the walk.
  Real inverse[3];
  bool parallel[3];
  for (int k = 0; k < 3; ++k) {
    parallel[k] = std::abs(d[k]) < Real(1e-30);
    inverse[k] = parallel[k] ? Real(0) : 1 / d[k];
  }
  const auto enter = [&](std::uint32_t node, Real& t) {
    const Aabb& box = nodes_[node].box;
    Real t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const Real lo = box.min[k] - inflate, hi = box.max[k] + inflate;
      if (parallel[k]) {
        if (o[k] < lo || o[k] > hi) return false;
        continue;
      }
      Real ta = (lo - o[k]) * inverse[k], tb = (hi - o[k]) * inverse[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    t = t0;
    return t0 <= t1;
  };
  Real t_root, t_max = 1;
  if (!enter(0, t_root)) return;
  stack[top++] = {0, t_root};
  while (top > 0) {
    const Pending pending = stack[--top];
    if (pending.t_enter > t_max) continue;
    const Node& node = nodes_[pending.node];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        t_max = std::min(t_max, visit(i));
      continue;
    }
    Real t_left = 0, t_right = 0;
    const bool left = enter(node.first, t_left) && t_left <= t_max;
    const bool right = enter(node.first + 1, t_right) && t_right <= t_max;
    if (top + 2 > 64) continue;
    if (left && right) {  // the nearer child on top
      const bool left_first = t_left <= t_right;
      stack[top++] = left_first ? Pending{node.first + 1, t_right} : Pending{node.first, t_left};
      stack[top++] = left_first ? Pending{node.first, t_left} : Pending{node.first + 1, t_right};
    } else if (left) {
      stack[top++] = {node.first, t_left};
    } else if (right) {
      stack[top++] = {node.first + 1, t_right};
    }
  }
}

}  // namespace ricochet::physics
