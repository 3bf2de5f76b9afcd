#pragma once
/// Uniform grid over body centres, rebuilt every step by a counting sort (no comparison sort, no
/// per-step allocation once warm). Dense when the box of occupied cells holds few cells per body
/// (a cell index is then direct arithmetic); hashed otherwise (sparse or far-flung scenes), with
/// a coordinate check against hash collisions. Entries of one cell stay in body-slot order, so
/// everything built from the grid is deterministic.

#include <cstdint>
#include <vector>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

struct BodyGrid {
  /// Everything the pair test needs, packed so the neighbour scan stays in cache.
  struct Entry {
    Vec3 position;         ///< m, body centre
    Real reach;            ///< m, radius + speculative margin
    std::int32_t x, y, z;  ///< cell
    std::uint32_t body;
  };

  Real cell_size = 1;  ///< m
  Real inverse_cell_size = 1;
  bool dense = false;
  std::int32_t min_cell[3] = {0, 0, 0};  ///< dense: lowest occupied cell
  std::int64_t extent[3] = {0, 0, 0};    ///< dense: cells per axis
  std::uint32_t shift = 32;              ///< hashed: 32 - log2(bucket count)
  std::vector<std::uint32_t>
      cell_start;                     ///< first entry per cell (dense) or bucket (hashed), plus end
  std::vector<Entry> entries;         ///< sorted by cell or bucket
  std::vector<Entry> unsorted;        ///< this step's entries in slot order (sort input)
  std::vector<std::uint32_t> key_of;  ///< per unsorted entry: its cell or bucket
  std::vector<std::uint32_t> cursor;  ///< counting-sort write positions
  /// The sorted entries' centres and reaches, one array per field for the packed pair test,
  /// followed by kLanePadding zeros so a pack may be loaded past the last entry.
  std::vector<Real> lane_x, lane_y, lane_z, lane_reach;
  static constexpr std::uint32_t kLanePadding = 8;

  /// Clamped so positions far beyond any arena cannot overflow the integer cell.
  std::int32_t coordinate(Real v) const;
  /// Sorts `unsorted` (already filled with cells computed by coordinate()) into `entries`.
  void build(Real cell);

  /// Cell index (dense) or bucket (hashed) of an occupied cell.
  std::uint32_t key(std::int32_t x, std::int32_t y, std::int32_t z) const {
    if (dense) {
      return static_cast<std::uint32_t>(
          ((std::int64_t{z} - min_cell[2]) * extent[1] + (std::int64_t{y} - min_cell[1])) *
              extent[0] +
          (std::int64_t{x} - min_cell[0]));
    }
    return hash(x, y, z);
  }

  /// Calls visit(entry) for every body whose centre lies in cell (x, y, z).
  template <class Visit>
  void visit_cell(std::int32_t x, std::int32_t y, std::int32_t z, Visit&& visit) const {
    if (entries.empty()) return;
    if (dense) {
      if (x < min_cell[0] || y < min_cell[1] || z < min_cell[2] ||
          std::int64_t{x} - min_cell[0] >= extent[0] ||
          std::int64_t{y} - min_cell[1] >= extent[1] ||
          std::int64_t{z} - min_cell[2] >= extent[2]) {
        return;
      }
      const std::uint32_t k = key(x, y, z);
      for (std::uint32_t e = cell_start[k]; e < cell_start[k + 1]; ++e) visit(entries[e]);
      return;
    }
    const std::uint32_t k = hash(x, y, z);
    for (std::uint32_t e = cell_start[k]; e < cell_start[k + 1]; ++e) {
      const Entry& entry = entries[e];
      if (entry.x == x && entry.y == y && entry.z == z) visit(entry);
    }
  }

 private:
  /// Fibonacci hashing of a Teschner-style key: the high bits spread neighbouring cells well.
  std::uint32_t hash(std::int32_t x, std::int32_t y, std::int32_t z) const {
    const std::uint32_t key = (static_cast<std::uint32_t>(x) * 73856093u) ^
                              (static_cast<std::uint32_t>(y) * 19349663u) ^
                              (static_cast<std::uint32_t>(z) * 83492791u);
    return (key * 0x9E3779B1u) >> shift;
  }
};

}  // namespace ricochet::physics
