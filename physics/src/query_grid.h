#pragma once
/// Uniform grid over body bounding boxes for queries between steps (queries.cpp).
///
/// The broadphase grid (body_grid.h) holds positions at step start and only the reach the pair
/// test needs, so after a step, or a set_transform, create or destroy between steps, it no
/// longer matches the bodies. This grid is built lazily from the bodies as they are: the first
/// query after any change rebuilds it (World marks it stale at the end of a step and in every
/// call that moves, creates or destroys a body; restore_state replaces the WorldImpl and with it
/// the grid). Building is two passes of a counting sort, O(bodies), with no allocation once warm.
///
/// A body is registered in every cell its box (grown by a rounding margin) overlaps, so a query
/// only visits the cells its own box overlaps:
///   - overlaps: the cells of the query sphere's box;
///   - casts: the segment is cut where it crosses cell planes (a 3D DDA), and each piece's box,
///     grown by the cast radius, visits its cells. The pieces cover the whole segment whatever the
///     rounding of the crossings, so the visited cells hold every body the swept sphere can touch
///     and the result equals the scan of every body slot.
/// The cell is 4 mean radii wide; the occupied box is kept under 4 cells per body plus 4096 by
/// widening the cell, and a body whose box spans more than 4 cells on an axis goes to a short
/// list tested by every query instead.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "body_store.h"
#include "geometry.h"

namespace ricochet::physics {

class QueryGrid {
 public:
  /// Rebuilds from the live bodies of `bodies` unless already current.
  void update(const BodyStore& bodies);
  void mark_stale() { current_ = false; }

  /// Calls visit(slot) for every body whose box can overlap `box`; a body may come more than once.
  template <class Visit>
  void visit_box(const Aabb& box, Visit&& visit) const;
  /// Calls visit(slot) for every body a sphere of radius `inflate` moved along o..o+d for
  /// t in [0, t_end] can touch, piece by piece along the segment in increasing t. After each piece
  /// done(t) is asked with the piece's end fraction; true stops the walk (every body not yet
  /// visited can only be touched after t). A body may come more than once.
  template <class Visit, class Done>
  void visit_segment(const Vec3& o, const Vec3& d, Real t_end, Real inflate, Visit&& visit,
                     Done&& done) const;

  /// Bodies in no cell (boxes too large for the grid), tested by every query.
  const std::vector<std::uint32_t>& large_bodies() const { return large_; }

 private:
  struct CellRange {
    std::int64_t lo[3], hi[3];
  };
  /// Cells overlapped by [lo, hi], clamped to the grid; empty when outside it.
  bool cells_of(const Vec3& lo, const Vec3& hi, CellRange& range) const;
  std::int64_t cell_index(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return (z * extent_[1] + y) * extent_[0] + x;
  }
  template <class Visit>
  void visit_cells(const CellRange& r, Visit&& visit) const {
    for (std::int64_t z = r.lo[2]; z <= r.hi[2]; ++z) {
      for (std::int64_t y = r.lo[1]; y <= r.hi[1]; ++y) {
        const std::int64_t row = cell_index(0, y, z);
        const std::uint32_t begin = cell_start_[static_cast<std::size_t>(row + r.lo[0])];
        const std::uint32_t end = cell_start_[static_cast<std::size_t>(row + r.hi[0] + 1)];
        for (std::uint32_t e = begin; e < end; ++e) visit(entries_[e]);
      }
    }
  }

  bool current_ = false;
  Vec3 origin_ = Vec3::Zero();  ///< m, low corner of cell (0, 0, 0)
  Vec3 bounds_hi_ = Vec3::Zero();
  Real cell_size_ = 1;  ///< m
  Real inverse_cell_size_ = 1;
  Real margin_ = 0;  ///< m, added around every box against rounding
  std::int64_t extent_[3] = {0, 0, 0};
  bool empty_ = true;
  std::vector<std::uint32_t> cell_start_;  ///< first entry per cell, plus the end
  std::vector<std::uint32_t> entries_;     ///< body slots, by cell, ascending slot within a cell
  std::vector<std::uint32_t> large_;
  std::vector<std::uint32_t> registered_;  ///< bodies in cells, ascending slot (build scratch)
  std::vector<CellRange> ranges_;          ///< per registered body (build scratch)
  std::vector<std::uint32_t> cursor_;      ///< counting-sort write positions (build scratch)
};

template <class Visit>
void QueryGrid::visit_box(const Aabb& box, Visit&& visit) const {
  CellRange range;
  if (cells_of(box.min, box.max, range)) visit_cells(range, visit);
}

template <class Visit, class Done>
void QueryGrid::visit_segment(const Vec3& o, const Vec3& d, Real t_end, Real inflate, Visit&& visit,
                              Done&& done) const {
  if (empty_) return;
  // Clip to the grid's box grown by the cast radius (slab test; nothing outside it can be hit).
  const Real grow = inflate + margin_;
  Real t0 = 0, t1 = t_end;
  for (int k = 0; k < 3; ++k) {
    const Real lo = origin_[k] - grow, hi = bounds_hi_[k] + grow;
    if (d[k] == 0) {
      if (o[k] < lo || o[k] > hi) return;
      continue;
    }
    Real a = (lo - o[k]) / d[k], b = (hi - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return;
  // Fractions where the segment crosses the next cell plane on each axis.
  Real next[3], step[3];
  const Vec3 start = o + d * t0;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      next[k] = step[k] = std::numeric_limits<Real>::infinity();
      continue;
    }
    const Real cell = std::floor((start[k] - origin_[k]) * inverse_cell_size_) + (d[k] > 0 ? 1 : 0);
    next[k] = (origin_[k] + cell * cell_size_ - o[k]) / d[k];
    step[k] = cell_size_ / std::abs(d[k]);
  }
  // A segment crosses at most extent planes per axis inside the grid; more pieces than that
  // means the crossings stopped advancing in floating point, and the rest is one piece.
  std::int64_t pieces_left = extent_[0] + extent_[1] + extent_[2] + 3;
  const Vec3 grow_piece = Vec3::Constant(inflate);
  Real t = t0;
  Vec3 from = start;
  for (;;) {
    const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const Real t_next = --pieces_left > 0 ? std::min(std::max(next[axis], t), t1) : t1;
    const Vec3 to = o + d * t_next;
    CellRange range;
    if (cells_of(from.cwiseMin(to) - grow_piece, from.cwiseMax(to) + grow_piece, range))
      visit_cells(range, visit);
    if (t_next >= t1 || done(t_next)) return;
    next[axis] += step[axis];
    t = t_next;
    from = to;
  }
}

}  // namespace ricochet::physics
