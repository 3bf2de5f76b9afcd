#!/usr/bin/env bash
# The test command: installs dependencies, then builds and runs every test four ways:
#   1. Release (-O3, GCC: what ./tools/run.sh builds), float physics
#   2. Debug with AddressSanitizer + UndefinedBehaviorSanitizer (clang 16: it builds this tree in
#      about 60 % of GCC's time), each gtest binary in shards (tests/CMakeLists.txt: a sanitized
#      process is slow to start); this tree also builds the libFuzzer targets (RICOCHET_FUZZ), so
#      the libraries they reach compile once for both
#   3. ThreadSanitizer (clang 16, -O1): the binaries whose code runs on several threads, the
#      database's (password threads, worker), the network layer's (server_tests; not match_tests,
#      the single-threaded match library: the live feed's hand-off between a match and its
#      viewers' threads is tested in server_tests for that) and the in-process integration tests
#      (control, tick and database threads of one Server); only their targets are built
#      The Java client's tests run in the Release pass only (no sanitizer sees into the JVM).
#   4. Release with double-precision physics (RICOCHET_DOUBLE=ON), physics tests only (and only
#      their targets are built)
# Warnings are errors in all four. Every libFuzzer target runs for 10 s (tools/fuzz.sh) beside the
# double pass's tests: a smoke run on its seeds and a little past them; fuzz longer with
# tools/fuzz.sh --seconds N.
# Each pass's tests run while the next pass builds (below).
# Before any of it, every C++ file must be as .clang-format (clang-format 14) formats it.
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
./tools/format.sh --check

jobs=$(nproc)
export CCACHE_DIR="${CCACHE_DIR:-$PWD/.ccache}"
export CCACHE_SLOPPINESS="${CCACHE_SLOPPINESS:-pch_defines,time_macros}"  # caches precompiled headers
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

times_file=$(mktemp)
# cpu_so_far: sets $cpu to the CPU seconds (user + system) of every process this script has waited
# for so far (bash's `times`, run in this shell: a subshell would see only its own children). Each
# phase's line shows it beside the elapsed time: on 2 cores the run is CPU-bound, so CPU is what
# a phase costs.
cpu=0
cpu_so_far() {
  times >"$times_file"
  cpu=$(awk 'NR == 2 { split($1, u, /[ms]/); split($2, s, /[ms]/)
                       printf "%.0f", u[1] * 60 + u[2] + s[1] * 60 + s[2] }' "$times_file")
}

lld=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld)  # lld-16 for the clang trees: less than half bfd's link time

# Each tree's tests run while the next tree builds: they mostly wait on sockets and timers (the
# Release tests keep a third of two cores busy), and the build, at nice 10, takes only what they
# leave idle. A pass's test output is printed whole when its tests end.

# build DIR TARGETS CMAKE_ARGS...: configures and builds DIR (TARGETS: a space-separated list,
# empty for everything).
build() {
  local dir=$1; shift
  local targets=$1; shift
  cpu_so_far
  echo "=== $dir: build (at ${SECONDS} s, CPU ${cpu} s) ==="
  cmake -S . -B "$dir" -G Ninja -DRICOCHET_WERROR=ON "${launcher[@]}" "$@"
  # shellcheck disable=SC2086  # a list of target names
  nice -n 10 cmake --build "$dir" -j "$jobs" ${targets:+--target $targets}
}

tests_pid=
tests_dir=
# start_tests DIR SELECT: runs DIR's tests (SELECT: ctest's selection options, empty for all) in
# the background, in a session of their own (the trap stops all of it); the caller's environment
# reaches them.
start_tests() {
  tests_dir=$1
  # shellcheck disable=SC2086  # a list of ctest options
  setsid --wait ctest --test-dir "$1" --output-on-failure -j "$jobs" --timeout 600 $2 \
    >"$1/ctest.log" 2>&1 &
  tests_pid=$!
}
# finish_tests: waits for the tests start_tests began, prints their output, fails when they did.
finish_tests() {
  local status=0
  wait "$tests_pid" || status=$?
  tests_pid=
  cpu_so_far
  echo "=== $tests_dir: tests (ended by ${SECONDS} s, CPU ${cpu} s) ==="
  cat "$tests_dir/ctest.log"
  return "$status"
}
trap 'if [[ -n $tests_pid ]]; then kill -- "-$tests_pid" 2>/dev/null || true; fi
      rm -f "$times_file"' EXIT

build build/release "" -DCMAKE_BUILD_TYPE=Release
start_tests build/release ""

build build/sanitize "" -DCMAKE_BUILD_TYPE=Debug -DRICOCHET_SANITIZE=address \
  -DCMAKE_CXX_COMPILER=clang++-16 "${lld[@]}" -DRICOCHET_TEST_SHARDS=8 -DRICOCHET_JAVA=OFF \
  -DRICOCHET_FUZZ=ON
finish_tests
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  start_tests build/sanitize ""

build build/tsan "db_tests server_tests integration_tests" -DCMAKE_BUILD_TYPE=Debug \
  -DRICOCHET_SANITIZE=thread -DCMAKE_CXX_COMPILER=clang++-16 "${lld[@]}" -DRICOCHET_TEST_SHARDS=8
finish_tests
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
  start_tests build/tsan "-R ^(db|server|integration)_tests_shard_"

build build/double "physics_tests physics_allocation_tests physics-bench arena-bench rewind-bench" \
  -DCMAKE_BUILD_TYPE=Release -DRICOCHET_DOUBLE=ON
finish_tests
start_tests build/double "-L physics"

cpu_so_far
echo "=== fuzzing (at ${SECONDS} s, CPU ${cpu} s) ==="
./tools/fuzz.sh --build-dir build/sanitize --seconds 10
finish_tests
cpu_so_far
echo "tools/test.sh: all tests passed in ${SECONDS} s (CPU ${cpu} s)"
