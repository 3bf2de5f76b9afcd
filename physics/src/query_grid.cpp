/// The query grid (query_grid.h): build and cell ranges.

#include "query_grid.h"

namespace ricochet::physics {

namespace {

constexpr std::int64_t kMaxSpan = 4;  ///< cells per axis; a wider body goes to the large list

}  // namespace

bool QueryGrid::cells_of(const Vec3& lo, const Vec3& hi, CellRange& range) const {
  for (int k = 0; k < 3; ++k) {
    const Real top = static_cast<Real>(extent_[k]);
    // Clamped before the conversion, so a box far outside cannot overflow the integer.
    const Real a =
        std::clamp(std::floor((lo[k] - margin_ - origin_[k]) * inverse_cell_size_), Real(-1), top);
    const Real b =
        std::clamp(std::floor((hi[k] + margin_ - origin_[k]) * inverse_cell_size_), Real(-1), top);
    if (b < 0 || a >= top) return false;
    range.lo[k] = std::max<std::int64_t>(static_cast<std::int64_t>(a), 0);
    range.hi[k] = std::min<std::int64_t>(static_cast<std::int64_t>(b), extent_[k] - 1);
  }
  return true;
}

void QueryGrid::update(const BodyStore& bodies) {
  if (current_) return;
  current_ = true;
  registered_.clear();
  large_.clear();
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::max());
  Vec3 hi = -lo;
  Real radius_sum = 0, largest_coordinate = 0;
  for (std::uint32_t s = 0; s < bodies.slot_count(); ++s) {
    if (!bodies.alive(s)) continue;
    const Vec3 r = Vec3::Constant(bodies.radius[s]);
    lo = lo.cwiseMin(bodies.position[s] - r);
    hi = hi.cwiseMax(bodies.position[s] + r);
    radius_sum += bodies.radius[s];
    largest_coordinate =
        std::max(largest_coordinate, bodies.position[s].cwiseAbs().maxCoeff() + bodies.radius[s]);
    registered_.push_back(s);
  }
  empty_ = registered_.empty();
  if (empty_) return;
  const std::int64_t count = static_cast<std::int64_t>(registered_.size());
  const std::int64_t max_cells = 4 * count + 4096;
  Real cell = 4 * radius_sum / static_cast<Real>(count);
  std::int64_t cells = 0;
  for (;;) {
    // Rounding of positions near largest_coordinate, and of fractions along a cast, stays far
    // below this margin.
    margin_ = cell / 1024 + 64 * std::numeric_limits<Real>::epsilon() * largest_coordinate;
    origin_ = lo - Vec3::Constant(margin_);
    bounds_hi_ = hi + Vec3::Constant(margin_);
    cells = 1;
    for (int k = 0; k < 3; ++k) {
      const Real span = std::floor((bounds_hi_[k] - origin_[k]) / cell) + 1;
      extent_[k] = static_cast<std::int64_t>(std::min(span, Real(max_cells)));
      cells = std::min(cells * extent_[k], max_cells + 1);
    }
    if (cells <= max_cells) break;
    cell *= 2;
  }
  cell_size_ = cell;
  inverse_cell_size_ = 1 / cell;

  // Cell ranges; bodies too wide for the grid move to the large list.
  ranges_.clear();
  std::size_t kept = 0;
  for (const std::uint32_t s : registered_) {
    const Vec3 r = Vec3::Constant(bodies.radius[s]);
    CellRange range;
    (void)cells_of(bodies.position[s] - r, bodies.position[s] + r, range);
    bool wide = false;
    for (int k = 0; k < 3; ++k) wide = wide || range.hi[k] - range.lo[k] >= kMaxSpan;
    if (wide) {
      large_.push_back(s);
      continue;
    }
    registered_[kept++] = s;
    ranges_.push_back(range);
  }
  registered_.resize(kept);

  // Counting sort of (cell, body) entries: slots stay ascending within a cell.
  const auto for_each_cell = [&](const CellRange& r, auto&& f) {
    for (std::int64_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (std::int64_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (std::int64_t x = r.lo[0]; x <= r.hi[0]; ++x)
          f(static_cast<std::size_t>(cell_index(x, y, z)));
  };
  cell_start_.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (const CellRange& r : ranges_) for_each_cell(r, [&](std::size_t c) { ++cell_start_[c + 1]; });
  for (std::size_t c = 0; c < static_cast<std::size_t>(cells); ++c)
    cell_start_[c + 1] += cell_start_[c];
  cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
  entries_.resize(cell_start_.back());
  for (std::size_t i = 0; i < registered_.size(); ++i) {
    for_each_cell(ranges_[i], [&](std::size_t c) { entries_[cursor_[c]++] = registered_[i]; });
  }
}

}  // namespace ricochet::physics
