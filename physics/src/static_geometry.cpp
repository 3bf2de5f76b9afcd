#include "static_geometry.h"

#include <algorithm>
#include <numeric>

namespace ricochet::physics {

namespace {
constexpr std::uint32_t kLeafSize = 4;
}

std::uint32_t StaticGeometry::add(StaticShape shape) {
  const std::uint32_t slot = slots_.acquire();
  if (shapes_.size() < slots_.slot_count()) shapes_.resize(slots_.slot_count());
  if (shape.type == ShapeType::Box) shape.box_rotation = shape.box_orientation.toRotationMatrix();
  shapes_[slot] = std::move(shape);
  rebuild_lists();
  return slot;
}

void StaticGeometry::remove(std::uint32_t slot) {
  shapes_[slot] = StaticShape{};
  slots_.release(slot);
  rebuild_lists();
}

void StaticGeometry::assign(SlotPool slots, std::vector<StaticShape> shapes) {
  slots_ = std::move(slots);
  shapes_ = std::move(shapes);
  for (StaticShape& s : shapes_) {
    if (s.type == ShapeType::Box) s.box_rotation = s.box_orientation.toRotationMatrix();
  }
  rebuild_lists();
}

void StaticGeometry::rebuild_lists() {
  plane_slots_.clear();
  primitives_.clear();
  for (std::uint32_t slot = 0; slot < shapes_.size(); ++slot) {
    if (!slots_.alive(slot)) continue;
    const StaticShape& s = shapes_[slot];
    switch (s.type) {
      case ShapeType::Plane:
        plane_slots_.push_back(slot);
        break;
      case ShapeType::Box:
        primitives_.push_back({slot, 0});
        break;
      case ShapeType::Mesh:
        for (std::uint32_t t = 0; t < s.indices.size() / 3; ++t) primitives_.push_back({slot, t});
        break;
    }
  }
  // Rebuilt at once (not at the next step) so queries between edits never see a stale tree.
  rebuild_tree();
}

void StaticGeometry::triangle(const StaticPrimitive& p, Vec3& a, Vec3& b, Vec3& c) const {
  const StaticShape& s = shapes_[p.shape];
  a = s.vertices[s.indices[3 * p.index]];
  b = s.vertices[s.indices[3 * p.index + 1]];
  c = s.vertices[s.indices[3 * p.index + 2]];
}

Aabb StaticGeometry::primitive_box(const StaticPrimitive& p) const {
  const StaticShape& s = shapes_[p.shape];
  Aabb box;
  if (s.type == ShapeType::Box) {
    const Vec3 extent = s.box_rotation.cwiseAbs() * s.box_half_extents;
    return {s.box_center - extent, s.box_center + extent};
  }
  Vec3 a, b, c;
  triangle(p, a, b, c);
  box.grow(a);
  box.grow(b);
  box.grow(c);
  return box;
}

void StaticGeometry::rebuild_tree() {
  nodes_.clear();
  primitive_boxes_.clear();
  if (primitives_.empty()) return;
  std::vector<Aabb> boxes(primitives_.size());
  std::vector<Vec3> centers(primitives_.size());
  for (std::size_t i = 0; i < primitives_.size(); ++i) {
    boxes[i] = primitive_box(primitives_[i]);
    centers[i] = boxes[i].center();
  }
  nodes_.reserve(2 * primitives_.size() / kLeafSize + 2);
  nodes_.emplace_back();
  build_node(0, 0, static_cast<std::uint32_t>(primitives_.size()), boxes, centers);
  primitive_boxes_ = std::move(boxes);  // sorted along with primitives_
}

void StaticGeometry::build_node(std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                                std::vector<Aabb>& boxes, std::vector<Vec3>& centers) {
  Aabb bounds, center_bounds;
  for (std::uint32_t i = begin; i < end; ++i) {
    bounds.grow(boxes[i]);
    center_bounds.grow(centers[i]);
  }
  nodes_[node].box = bounds;
  // Depth stays below the traversal stack size: a median split halves the range each level.
  if (end - begin <= kLeafSize) {
    nodes_[node].first = begin;
    nodes_[node].count = end - begin;
    return;
  }
  int axis = 0;
  const Vec3 extent = center_bounds.max - center_bounds.min;
  if (extent.y() > extent[axis]) axis = 1;
  if (extent.z() > extent[axis]) axis = 2;
  const std::uint32_t mid = begin + (end - begin) / 2;
  // Sort the range by centre along the axis (stable tie-break by primitive order: deterministic).
  std::vector<std::uint32_t> order(end - begin);
  std::iota(order.begin(), order.end(), begin);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return centers[a][axis] < centers[b][axis];
  });
  std::vector<StaticPrimitive> prims(order.size());
  std::vector<Aabb> sorted_boxes(order.size());
  std::vector<Vec3> sorted_centers(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    prims[k] = primitives_[order[k]];
    sorted_boxes[k] = boxes[order[k]];
    sorted_centers[k] = centers[order[k]];
  }
  std::copy(prims.begin(), prims.end(), primitives_.begin() + begin);
  std::copy(sorted_boxes.begin(), sorted_boxes.end(), boxes.begin() + begin);
  std::copy(sorted_centers.begin(), sorted_centers.end(), centers.begin() + begin);

  const std::uint32_t left = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nodes_[node].first = left;
  nodes_[node].count = 0;
  build_node(left, begin, mid, boxes, centers);
  build_node(left + 1, mid, end, boxes, centers);
}

ClosestFeature StaticGeometry::closest_feature(std::uint32_t primitive, const Vec3& point) const {
  const StaticPrimitive& p = primitives_[primitive];
  const StaticShape& s = shapes_[p.shape];
  if (s.type == ShapeType::Box) {
    const Vec3 local = s.box_rotation.transpose() * (point - s.box_center);
    const Vec3& h = s.box_half_extents;
    const Vec3 clamped = local.cwiseMax(-h).cwiseMin(h);
    if (clamped != local) {
      Vec3 n = local - clamped;
      const Real dist = n.norm();
      n /= dist;
      return {s.box_center + s.box_rotation * clamped, s.box_rotation * n, dist, true};
    }
    // Inside: push out through the nearest face.
    int axis = 0;
    Real best = h.x() - std::abs(local.x());
    for (int k = 1; k < 3; ++k) {
      const Real depth = h[k] - std::abs(local[k]);
      if (depth < best) {
        best = depth;
        axis = k;
      }
    }
    Vec3 n = Vec3::Zero();
    n[axis] = local[axis] >= 0 ? Real(1) : Real(-1);
    Vec3 surface = local;
    surface[axis] = n[axis] * h[axis];
    return {s.box_center + s.box_rotation * surface, s.box_rotation * n, -best, true};
  }
  Vec3 a, b, c;
  triangle(p, a, b, c);
  const Vec3 q = closest_point_on_triangle(point, a, b, c);
  Vec3 face = (b - a).cross(c - a);
  const Real face_len = face.norm();
  face = face_len > 0 ? Vec3(face / face_len) : fallback_normal();
  Vec3 n = point - q;
  const Real dist = n.norm();
  // Inside the face when the offset is along the face normal only.
  const Vec3 sideways = n - face * face.dot(n);
  const bool on_face = sideways.squaredNorm() <= Real(1e-8) * (dist * dist) + Real(1e-12);
  if (dist > Real(1e-12) * (Real(1) + point.norm())) {
    n /= dist;
  } else {
    n = face;  // centre on the triangle: the winding side
  }
  return {q, n, dist, on_face};
}

bool StaticGeometry::sweep(std::uint32_t primitive, const Vec3& o, const Vec3& d, Real radius,
                           SweepHit& hit) const {
  // A primitive whose box the swept sphere's box misses by more than a millimetre cannot be
  // hit, which the exact sweep below would find too, at many times the cost. A leaf of the
  // hierarchy holds several primitives, and most casts (a ground probe, a short step) touch one.
  constexpr Real kRejectMargin = Real(1e-3);
  Aabb path = Aabb::around_sphere(o, radius + kRejectMargin);
  path.grow(Aabb::around_sphere(o + d, radius + kRejectMargin));
  if (!path.overlaps(primitive_boxes_[primitive])) return false;
  const StaticPrimitive& p = primitives_[primitive];
  const StaticShape& s = shapes_[p.shape];
  if (s.type == ShapeType::Box) {
    const Mat3 to_local = s.box_rotation.transpose();
    SweepHit local_hit = hit;
    if (!sweep_sphere_local_box(to_local * (o - s.box_center), to_local * d, radius,
                                s.box_half_extents, local_hit)) {
      return false;
    }
    hit.t = local_hit.t;
    hit.normal = s.box_rotation * local_hit.normal;
    return true;
  }
  Vec3 a, b, c;
  triangle(p, a, b, c);
  return sweep_sphere_triangle(o, d, radius, a, b, c, hit);
}

}  // namespace ricochet::physics
