#!/usr/bin/env bash
# The restore_state fuzzer (tests/fuzz): builds it with clang, libFuzzer, ASan and UBSan into
# build/fuzz, then fuzzes a temporary copy of the seed corpus, so the repo's corpus stays as is.
#   tools/fuzz.sh [--seconds N] [-flag=value ...]   fuzz for N seconds (default 45); -flag=value
#                                                   goes to libFuzzer (-runs=100000, -fork=2 ...)
#   tools/fuzz.sh --seeds                           rewrite tests/fuzz/corpus/restore_state/
#                                                   (after an image format change)
# Exits non-zero when the fuzzer finds a crash, a leak or a timeout, and prints the reproducer's
# path; replay one with `build/fuzz/restore_state_fuzz PATH`.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=45
seeds=0
passthrough=()
while (($#)); do
  case $1 in
    --seconds) seconds=${2:-}; shift 2 || shift ;;
    --seconds=*) seconds=${1#*=}; shift ;;
    --seeds) seeds=1; shift ;;
    -h | --help) sed -n '2,9p' "$0"; exit 0 ;;
    -*=*) passthrough+=("$1"); shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (see tools/fuzz.sh --help)" >&2; exit 2 ;;
  esac
done
if ! [[ $seconds =~ ^[0-9]+$ ]] || ((seconds == 0)); then
  echo "fuzz.sh: --seconds wants a whole number of seconds > 0, got '$seconds'" >&2
  exit 2
fi

dir=build/fuzz
corpus=tests/fuzz/corpus/restore_state
export CCACHE_DIR="${CCACHE_DIR:-$PWD/.ccache}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

echo "=== $dir ==="
cmake -S tests/fuzz -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}"
cmake --build "$dir" -j "$(nproc)"

export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if ((seeds)); then
  rm -f "$corpus"/*.bin
  "$dir/make_seeds" "$corpus"
  exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$corpus"/* "$work"/
artifacts="$dir/artifacts/$(date +%Y%m%d-%H%M%S)"
mkdir -p "$artifacts"
log="$dir/last-run.log"
echo "fuzz.sh: restore_state for ${seconds} s on a copy of $corpus ($(ls "$corpus" | wc -l) seeds)"
status=0
"$dir/restore_state_fuzz" -max_total_time="$seconds" -max_len=65536 -timeout=10 \
  -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts/" "${passthrough[@]}" \
  "$work" >"$log" 2>&1 || status=$?
grep -E '^#[0-9]+[[:space:]]+(INITED|pulse|DONE)|^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)|^Done ' \
  "$log" || true
if ((status != 0)); then
  tail -n 60 "$log"
  echo "fuzz.sh: the fuzzer failed (exit $status); full log in $log" >&2
  for reproducer in "$artifacts"/*; do
    [[ -e $reproducer ]] || continue
    echo "fuzz.sh: reproducer $reproducer (replay: $dir/restore_state_fuzz $reproducer)" >&2
  done
  exit 1
fi
rmdir "$artifacts" 2>/dev/null || true
echo "fuzz.sh: no crash found; $(ls "$work" | wc -l) inputs in the final corpus"
