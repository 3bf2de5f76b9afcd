#!/usr/bin/env bash
# Runs the rain scene in Ricochet and, when built, in Bullet and ODE, at each body count; keeps
# the median of --repeat runs per engine and size, writes them as JSON Lines to
# tools/bench/results/rain.jsonl and prints Ricochet's ms/step as a ratio of the faster peer.
#
#   tools/bench/compare_rain.sh [--repeat 3] [--sizes "256 1024 4096 16384"] [--build build/release]
#
# Build the peers first with: RICOCHET_PEERS=1 ./tools/deps.sh &&
#   cmake -S . -B build/release -DRICOCHET_PEER_BENCH=ON && cmake --build build/release
set -euo pipefail
cd "$(dirname "$0")/../.."
repeat=3
sizes="256 1024 4096 16384"
build=build/release
while (($#)); do
  case "$1" in
    --repeat) repeat=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
out=tools/bench/results/rain.jsonl
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

engines=(ricochet)
[[ -x $build/tools/bench/peers/physics-bench-bullet ]] && engines+=(bullet)
[[ -x $build/tools/bench/peers/physics-bench-ode ]] && engines+=(ode)
binary() {
  case "$1" in
    ricochet) echo "$build/tools/bench/physics-bench" ;;
    *) echo "$build/tools/bench/peers/physics-bench-$1" ;;
  esac
}
ms_of() { sed -E 's/.*"ms_per_step":([0-9.eE+-]+).*/\1/' <<<"$1"; }

: >"$tmp/all.jsonl"
for n in $sizes; do
  for engine in "${engines[@]}"; do
    : >"$tmp/runs"
    for ((r = 0; r < repeat; ++r)); do
      line=$("$(binary "$engine")" --bodies "$n")
      printf '%s %s\n' "$(ms_of "$line")" "$line" >>"$tmp/runs"
    done
    # Median by ms/step.
    sort -g "$tmp/runs" | sed -n "$(((repeat + 1) / 2))p" | cut -d' ' -f2- >>"$tmp/all.jsonl"
    echo "done: $engine $n" >&2
  done
done
cp "$tmp/all.jsonl" "$out"

printf '%-7s %-9s %12s %16s %8s %5s\n' bodies engine ms/step max_pen_mm escaped nan
while read -r line; do
  n=$(sed -E 's/.*"bodies":([0-9]+).*/\1/' <<<"$line")
  engine=$(sed -E 's/.*"engine":"([a-z]+)".*/\1/' <<<"$line")
  pen=$(sed -E 's/.*"max_penetration":([0-9.eE+-]+).*/\1/' <<<"$line")
  esc=$(sed -E 's/.*"escaped":([0-9]+).*/\1/' <<<"$line")
  nan=$(sed -E 's/.*"nan":([0-9]+).*/\1/' <<<"$line")
  printf '%-7s %-9s %12.3f %16.2f %8s %5s\n' "$n" "$engine" "$(ms_of "$line")" "$(awk "BEGIN{print $pen*1000}")" "$esc" "$nan"
done <"$out"
if ((${#engines[@]} > 1)); then
  echo
  echo "Ricochet ms/step as a fraction of the faster peer's (target <= 0.2):"
  for n in $sizes; do
    awk -v n="$n" '
      { match($0, /"bodies":[0-9]+/); b = substr($0, RSTART + 9, RLENGTH - 9);
        match($0, /"engine":"[a-z]+"/); e = substr($0, RSTART + 10, RLENGTH - 11);
        match($0, /"ms_per_step":[0-9.eE+-]+/); m = substr($0, RSTART + 14, RLENGTH - 14) + 0;
        if (b == n) { if (e == "ricochet") r = m; else if (best == 0 || m < best) { best = m; peer = e } } }
      END { if (best > 0) printf "  %6d bodies: %.3f of %s\n", n, r / best, peer }' "$out"
  done
fi
echo "results: $out"
