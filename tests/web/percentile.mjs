// The one percentile definition of every figure (stats/include/ricochet/stats/percentile.h, the
// benches, /metrics, the bot and the load test): nearest rank, the smallest value with at least
// q of the values at or below it; q = 1 is the maximum. `values` must not be empty.
export function nearestRank(values, q) {
  const sorted = [...values].sort((a, b) => a - b);
  const rank = Math.max(1, Math.ceil(q * sorted.length));
  return sorted[Math.min(sorted.length, rank) - 1];
}
