#!/usr/bin/env bash
# The libFuzzer targets (tests/fuzz): builds them with clang 16, libFuzzer, ASan and UBSan into
# build/fuzz (the main project with -DRICOCHET_FUZZ=ON), then fuzzes each target NAME_fuzz on a
# temporary copy of its seed corpus tests/fuzz/corpus/NAME/, so the repo's corpora stay as they are.
#   tools/fuzz.sh [--seconds N] [--jobs J] [--only NAME] [-flag=value ...]
#                          fuzz every target (or one) for N seconds each (default 30), J targets
#                          at a time (default: the number of cores); -flag=value goes to
#                          libFuzzer (-runs=100000, -fork=2 ...)
#   tools/fuzz.sh --seeds  rewrite every corpus that has a writer (tests/fuzz/NAME_seeds.cpp),
#                          after a format change
#   --build-dir DIR        use the targets of DIR, a tree configured with -DRICOCHET_FUZZ=ON
#                          (tools/test.sh passes its sanitized tree, which builds them)
# Exits non-zero when a fuzzer finds a crash, a leak or a timeout, and prints the reproducer's
# path; replay one with `build/fuzz/tests/fuzz/NAME_fuzz PATH`.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=30
jobs=$(nproc)
seeds=0
dir=
only=
passthrough=()
while (($#)); do
  case $1 in
    --seconds) seconds=${2:-}; shift 2 || shift ;;
    --seconds=*) seconds=${1#*=}; shift ;;
    --jobs) jobs=${2:-}; shift 2 || shift ;;
    --jobs=*) jobs=${1#*=}; shift ;;
    --only) only=${2:-}; shift 2 || shift ;;
    --only=*) only=${1#*=}; shift ;;
    --seeds) seeds=1; shift ;;
    --build-dir) dir=${2:-}; shift 2 || shift ;;
    --build-dir=*) dir=${1#*=}; shift ;;
    -h | --help) sed -n '2,15p' "$0"; exit 0 ;;
    -*=*) passthrough+=("$1"); shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (see tools/fuzz.sh --help)" >&2; exit 2 ;;
  esac
done
if ! [[ $seconds =~ ^[0-9]+$ ]] || ((seconds == 0)); then
  echo "fuzz.sh: --seconds wants a whole number of seconds > 0, got '$seconds'" >&2
  exit 2
fi
if ! [[ $jobs =~ ^[0-9]+$ ]] || ((jobs == 0)); then
  echo "fuzz.sh: --jobs wants a whole number > 0, got '$jobs'" >&2
  exit 2
fi

if [[ -z $dir ]]; then
  dir=build/fuzz
  export CCACHE_DIR="${CCACHE_DIR:-$PWD/.ccache}"
  launcher=()
  if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  echo "=== $dir ==="
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DRICOCHET_SANITIZE=address \
    -DRICOCHET_FUZZ=ON -DRICOCHET_JAVA=OFF -DCMAKE_CXX_COMPILER=clang++-16 "${launcher[@]}" \
    -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld  # lld-16: links the sanitized targets in half bfd's time
fi
if [[ ! -f $dir/CMakeCache.txt ]] || ! grep -q '^RICOCHET_FUZZ:BOOL=ON$' "$dir/CMakeCache.txt"; then
  echo "fuzz.sh: $dir is not a tree configured with -DRICOCHET_FUZZ=ON" >&2
  exit 2
fi
cmake --build "$dir" -j "$(nproc)" --target fuzz_targets
bin=$dir/tests/fuzz

export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
names=()
for target in tests/fuzz/*_fuzz.cpp; do
  name=$(basename "$target" _fuzz.cpp)
  if [[ -z $only || $only == "$name" ]]; then names+=("$name"); fi
done
if ((${#names[@]} == 0)); then
  echo "fuzz.sh: no target named '$only' (tests/fuzz/*_fuzz.cpp)" >&2
  exit 2
fi

if ((seeds)); then
  for name in "${names[@]}"; do
    [[ -x $bin/${name}_seeds ]] || continue
    mkdir -p "tests/fuzz/corpus/$name"
    rm -f "tests/fuzz/corpus/$name"/*
    "$bin/${name}_seeds" "tests/fuzz/corpus/$name"
    echo "fuzz.sh: wrote $(ls "tests/fuzz/corpus/$name" | wc -l) seeds into tests/fuzz/corpus/$name"
  done
  exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# fuzz_one NAME: fuzzes one target on a copy of its corpus; prints its summary into
# $work/NAME.out (so that targets run side by side never interleave their lines); fails when the
# fuzzer found something.
fuzz_one() {
  local name=$1
  local corpus=tests/fuzz/corpus/$name
  if [[ ! -d $corpus ]] || [[ -z $(ls -A "$corpus") ]]; then
    echo "fuzz.sh: $name has no seed corpus in $corpus" >&2
    return 1
  fi
  mkdir -p "$work/$name"
  cp "$corpus"/* "$work/$name"/
  local artifacts
  artifacts="$dir/artifacts/$name-$(date +%Y%m%d-%H%M%S)"
  mkdir -p "$artifacts"
  local log="$dir/last-run-$name.log"
  echo "fuzz.sh: $name for ${seconds} s on a copy of $corpus ($(ls "$corpus" | wc -l) seeds)"
  local status=0
  "$bin/${name}_fuzz" -max_total_time="$seconds" -max_len=65536 -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts/" "${passthrough[@]}" \
    "$work/$name" >"$log" 2>&1 || status=$?
  grep -E '^#[0-9]+[[:space:]]+(INITED|DONE)|^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)|^Done ' \
    "$log" || true
  if ((status != 0)); then
    tail -n 60 "$log"
    echo "fuzz.sh: $name failed (exit $status); full log in $log" >&2
    for reproducer in "$artifacts"/*; do
      [[ -e $reproducer ]] || continue
      echo "fuzz.sh: reproducer $reproducer (replay: $bin/${name}_fuzz $reproducer)" >&2
    done
    return 1
  fi
  rmdir "$artifacts" 2>/dev/null || true
  echo "fuzz.sh: $name: no crash found; $(ls "$work/$name" | wc -l) inputs in the final corpus"
}

# Up to $jobs targets at a time; each one's summary is printed when it ends.
failed=0
declare -A running=()  # pid -> name
report() {  # report PID STATUS
  local name=${running[$1]}
  unset "running[$1]"
  cat "$work/$name.out"
  if (($2 != 0)); then failed=1; fi
}
wait_for_one() {
  local pid status=0
  wait -n -p pid "${!running[@]}" || status=$?
  report "$pid" "$status"
}
for name in "${names[@]}"; do
  while ((${#running[@]} >= jobs)); do wait_for_one; done
  fuzz_one "$name" >"$work/$name.out" 2>&1 &
  running[$!]=$name
done
while ((${#running[@]} > 0)); do wait_for_one; done
exit "$failed"
