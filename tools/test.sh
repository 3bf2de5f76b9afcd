#!/usr/bin/env bash
# The test command: installs dependencies, then builds and runs every test four ways:
#   1. Release (-O3, GCC: what ./tools/run.sh builds), float physics
#   2. Debug with AddressSanitizer + UndefinedBehaviorSanitizer (clang 16: it builds this tree in
#      about 60 % of GCC's time), each gtest binary in shards (tests/CMakeLists.txt: a sanitized
#      process is slow to start)
#   3. ThreadSanitizer (clang 16, -O1): the binaries whose code runs on several threads, the
#      database's (password threads, worker), the server's and the in-process integration tests
#      (control, tick and database threads of one Server); only their targets are built
#   4. Release with double-precision physics (RICOCHET_DOUBLE=ON), physics tests only (and only
#      their targets are built)
# Warnings are errors in all four. Then every libFuzzer target runs for 20 s (tools/fuzz.sh).
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

# build_and_test DIR SELECT TARGETS CMAKE_ARGS...: SELECT (ctest's test selection options) and
# TARGETS empty for everything; both are space-separated lists.
build_and_test() {
  local dir=$1; shift
  local select=$1; shift
  local targets=$1; shift
  echo "=== $dir ==="
  cmake -S . -B "$dir" -G Ninja -DRICOCHET_WERROR=ON "${launcher[@]}" "$@"
  if [[ -n "$targets" ]]; then
    # shellcheck disable=SC2086  # a list of target names
    cmake --build "$dir" -j "$jobs" --target $targets
  else
    cmake --build "$dir" -j "$jobs"
  fi
  # shellcheck disable=SC2086  # a list of ctest options
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" --timeout 600 $select
}

build_and_test build/release "" "" -DCMAKE_BUILD_TYPE=Release
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  build_and_test build/sanitize "" "" -DCMAKE_BUILD_TYPE=Debug -DRICOCHET_SANITIZE=address \
  -DCMAKE_CXX_COMPILER=clang++-16 -DRICOCHET_TEST_SHARDS=8
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
  build_and_test build/tsan "-R ^(db|server|integration)_tests_shard_" \
  "db_tests server_tests integration_tests" -DCMAKE_BUILD_TYPE=Debug -DRICOCHET_SANITIZE=thread \
  -DCMAKE_CXX_COMPILER=clang++-16 -DRICOCHET_TEST_SHARDS=8
build_and_test build/double "-L physics" \
  "physics_tests physics_allocation_tests physics-bench arena-bench rewind-bench" \
  -DCMAKE_BUILD_TYPE=Release -DRICOCHET_DOUBLE=ON
./tools/fuzz.sh --seconds 20
echo "tools/test.sh: all tests passed"
