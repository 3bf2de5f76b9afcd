/// Broadphase: a uniform hash grid over body centres, rebuilt every step by a counting sort.
///
/// The cell is at least as wide as the largest interaction distance (two radii plus two
/// speculative margins), so every candidate pair lies in the same or an adjacent cell. Visiting
/// the own cell plus the 13 "forward" neighbours finds each pair exactly once, in O(n) for evenly
/// spread spheres. The order is deterministic: entries are stable-sorted by bucket, then by slot.
/// Chosen over sort-and-sweep, whose sweep axis meets a whole slab of a wide, flat pile.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

constexpr std::int32_t kForwardNeighbours[13][3] = {
    {1, 0, 0},  {-1, 1, 0}, {0, 1, 0}, {1, 1, 0},  {-1, -1, 1}, {0, -1, 1}, {1, -1, 1},
    {-1, 0, 1}, {0, 0, 1},  {1, 0, 1}, {-1, 1, 1}, {0, 1, 1},   {1, 1, 1},
};

/// A pack of consecutive grid entries' values, one SSE2/NEON register (4 floats, 2 doubles).
using Pack = Real __attribute__((vector_size(16)));
constexpr std::uint32_t kPackWidth = sizeof(Pack) / sizeof(Real);
static_assert(kPackWidth <= BodyGrid::kLanePadding);

Pack splat(Real v) {
  Pack p;
  for (std::uint32_t l = 0; l < kPackWidth; ++l) p[l] = v;
  return p;
}

Pack load(const Real* p) {
  Pack v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// Bit l set when a[l] < b[l] (false for NaN, as the scalar comparison).
unsigned lanes_below(Pack a, Pack b) {
  const auto below = a < b;  // lanes all ones or all zeros
#if defined(__SSE2__) && !defined(RICOCHET_DOUBLE)
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(below)));
#elif defined(__SSE2__)
  return static_cast<unsigned>(_mm_movemask_pd(reinterpret_cast<__m128d>(below)));
#else
  unsigned bits = 0;
  for (std::uint32_t l = 0; l < kPackWidth; ++l) bits |= (below[l] != 0 ? 1u : 0u) << l;
  return bits;
#endif
}

std::uint32_t next_power_of_two(std::uint32_t v) {
  std::uint32_t p = 1;
  while (p < v) p <<= 1;
  return p;
}

}  // namespace

std::int32_t BodyGrid::coordinate(Real v) const {
  const Real c = std::floor(v * inverse_cell_size);
  return static_cast<std::int32_t>(std::clamp(c, Real(-1e9), Real(1e9)));
}

void BodyGrid::build(Real cell) {
  cell_size = cell;
  inverse_cell_size = 1 / cell;
  const std::uint32_t count = static_cast<std::uint32_t>(unsorted.size());
  std::int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
  for (Entry& e : unsorted) {
    e.x = coordinate(e.position.x());
    e.y = coordinate(e.position.y());
    e.z = coordinate(e.position.z());
    const std::int32_t c[3] = {e.x, e.y, e.z};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k]);
      hi[k] = std::max(hi[k], c[k]);
    }
  }
  std::int64_t cells = 1;
  for (int k = 0; k < 3; ++k) {
    min_cell[k] = lo[k];
    extent[k] = std::int64_t{hi[k]} - lo[k] + 1;
    // Saturating: extents reach 2^32 when bodies are far apart, so the product could overflow.
    constexpr std::int64_t kCap = std::int64_t{1} << 40;
    cells = extent[k] > kCap / cells ? kCap : std::min(cells * extent[k], kCap);
  }
  dense = cells <= 4 * std::int64_t{count} + 4096;
  std::uint32_t keys;
  key_of.resize(count);
  if (dense) {
    keys = static_cast<std::uint32_t>(cells);
  } else {
    keys = next_power_of_two(std::max<std::uint32_t>(2 * count, 16));
    shift = 32 - static_cast<std::uint32_t>(std::countr_zero(keys));
  }
  for (std::uint32_t i = 0; i < count; ++i)
    key_of[i] = key(unsorted[i].x, unsorted[i].y, unsorted[i].z);
  assign_reusing(cell_start, keys + 1, 0);
  for (std::uint32_t i = 0; i < count; ++i) ++cell_start[key_of[i] + 1];
  for (std::uint32_t k = 0; k < keys; ++k) cell_start[k + 1] += cell_start[k];
  assign_reusing(cursor, cell_start.begin(), cell_start.end() - 1);
  entries.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) entries[cursor[key_of[i]]++] = unsorted[i];
  for (std::vector<Real>* lane : {&lane_x, &lane_y, &lane_z, &lane_reach})
    lane->resize(std::size_t{count} + kLanePadding);
  for (std::uint32_t i = 0; i < count; ++i) {
    lane_x[i] = entries[i].position.x();
    lane_y[i] = entries[i].position.y();
    lane_z[i] = entries[i].position.z();
    lane_reach[i] = entries[i].reach;
  }
  for (std::uint32_t i = count; i < count + kLanePadding; ++i)
    lane_x[i] = lane_y[i] = lane_z[i] = lane_reach[i] = 0;
}

[[gnu::flatten]] void WorldImpl::find_pairs() {
  scratch.pairs.clear();
  scratch.sensor_pairs.clear();
  scratch.grid.unsorted.clear();
  Real max_reach = 0;
  for (std::uint32_t s = 0; s < state.bodies.slot_count(); ++s) {
    if (!state.bodies.alive(s)) continue;
    const Real reach = state.bodies.radius[s] + scratch.speculative_margin[s];
    max_reach = std::max(max_reach, reach);
    scratch.grid.unsorted.push_back(BodyGrid::Entry{state.bodies.position[s], reach, 0, 0, 0, s});
  }
  scratch.grid.entries.clear();
  if (scratch.grid.unsorted.empty()) return;
  // Every pair within reach then lies in the same or a neighbouring cell.
  scratch.grid.build(2 * max_reach);

  // Bodies within reach of each other: filtered by state, kind and layers, then recorded.
  const auto accept = [&](const BodyGrid::Entry& ei, const BodyGrid::Entry& ej) {
    const std::uint32_t i = ei.body, j = ej.body;
    const std::uint16_t fi = state.bodies.flags[i], fj = state.bodies.flags[j];
    const bool active_i = (fi & (kFlagSleeping | kFlagFrozen)) == 0;
    const bool active_j = (fj & (kFlagSleeping | kFlagFrozen)) == 0;
    if (!active_i && !active_j) {
      // Two resting bodies: only sleeping islands need the link (to wake together).
      if (!def.enable_sleep || ((fi | fj) & kFlagFrozen) != 0) return;
    }
    if ((fi & fj & kFlagKinematic) != 0) return;
    if (!collides(state.bodies.filter[i], state.bodies.filter[j])) return;
    const BodyPair pair{std::min(i, j), std::max(i, j)};
    if (((fi | fj) & kFlagSensor) != 0) {
      scratch.sensor_pairs.push_back(pair);
    } else {
      scratch.pairs.push_back(pair);
    }
  };

  const BodyGrid::Entry* entries = scratch.grid.entries.data();
  const std::uint32_t entry_count = static_cast<std::uint32_t>(scratch.grid.entries.size());
  const auto within_reach = [](const BodyGrid::Entry& ei, const BodyGrid::Entry& ej) {
    const Real reach = ei.reach + ej.reach;
    return (ej.position - ei.position).squaredNorm() < reach * reach;
  };
  // Entry e against the consecutive entries [begin, end): the distance test runs branch-free on
  // packs of consecutive entries read from the grid's per-field lanes (most candidates miss, and
  // a mispredicted branch costs more than the test), then the hits are accepted in order. Each
  // lane computes what within_reach does, operation for operation, so the same pairs are found.
  const Real* const lane_x = scratch.grid.lane_x.data();
  const Real* const lane_y = scratch.grid.lane_y.data();
  const Real* const lane_z = scratch.grid.lane_z.data();
  const Real* const lane_reach = scratch.grid.lane_reach.data();
  // The scanning entry's centre and reach in every lane (set by aim, once per entry).
  Pack mx, my, mz, mr;
  const auto aim = [&](const BodyGrid::Entry& me) {
    mx = splat(me.position.x());
    my = splat(me.position.y());
    mz = splat(me.position.z());
    mr = splat(me.reach);
  };
  const auto scan = [&](std::uint32_t e, std::uint32_t begin, std::uint32_t end) {
    const BodyGrid::Entry& me = entries[e];
    // The pack at f, its lanes limited to those in mask.
    const auto test = [&](std::uint32_t f, unsigned mask) {
      const Pack dx = load(lane_x + f) - mx, dy = load(lane_y + f) - my, dz = load(lane_z + f) - mz;
      const Pack reach = mr + load(lane_reach + f);
      unsigned hits = lanes_below((dx * dx + dy * dy) + dz * dz, reach * reach) & mask;
      for (; hits != 0; hits &= hits - 1)
        accept(me, entries[f + static_cast<std::uint32_t>(std::countr_zero(hits))]);
    };
    std::uint32_t f = begin;
    for (; f + kPackWidth <= end; f += kPackWidth) test(f, (1u << kPackWidth) - 1);
    if (f < end) test(f, (1u << (end - f)) - 1);
  };
  if (scratch.grid.dense) {
    // Cells of one x-row are consecutive, so each neighbour row is one contiguous range:
    // the rest of this cell plus cell x+1, then rows (y+1, z), (y-1..y+1, z+1) over x-1..x+1.
    constexpr std::int32_t kRows[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    const std::int64_t nx = scratch.grid.extent[0], ny = scratch.grid.extent[1],
                       nz = scratch.grid.extent[2];
    for (std::uint32_t e = 0; e < entry_count; ++e) {
      const BodyGrid::Entry& me = entries[e];
      const std::int64_t x = me.x - scratch.grid.min_cell[0], y = me.y - scratch.grid.min_cell[1],
                         z = me.z - scratch.grid.min_cell[2];
      const std::int64_t row = (z * ny + y) * nx;
      aim(me);
      scan(e, e + 1, scratch.grid.cell_start[row + std::min(x + 1, nx - 1) + 1]);
      for (const auto& r : kRows) {
        const std::int64_t ry = y + r[0], rz = z + r[1];
        if (ry < 0 || ry >= ny || rz >= nz) continue;
        const std::int64_t other_row = (rz * ny + ry) * nx;
        scan(e, scratch.grid.cell_start[other_row + std::max<std::int64_t>(x - 1, 0)],
             scratch.grid.cell_start[other_row + std::min(x + 1, nx - 1) + 1]);
      }
    }
  } else {
    for (std::uint32_t e = 0; e < entry_count; ++e) {
      const BodyGrid::Entry& me = entries[e];
      // Same cell: the entries after this one in its bucket, checked by coordinates.
      const std::uint32_t bucket_end =
          scratch.grid.cell_start[scratch.grid.key(me.x, me.y, me.z) + 1];
      for (std::uint32_t f = e + 1; f < bucket_end; ++f) {
        const BodyGrid::Entry& other = entries[f];
        if (other.x == me.x && other.y == me.y && other.z == me.z && within_reach(me, other))
          accept(me, other);
      }
      for (const auto& offset : kForwardNeighbours) {
        scratch.grid.visit_cell(me.x + offset[0], me.y + offset[1], me.z + offset[2],
                                [&](const BodyGrid::Entry& other) {
                                  if (within_reach(me, other)) accept(me, other);
                                });
      }
    }
  }
  profile.pair_candidates = static_cast<int>(scratch.pairs.size());
}

}  // namespace ricochet::physics
