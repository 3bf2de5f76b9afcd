#!/usr/bin/env bash
# The live view's frame time in headless Chromium with a full match (tests/web/live_view.bench.mjs):
# appends one JSON line to tools/bench/results/live_view.jsonl. Needs a Release tree with the
# server, the load test and the browser tests' node_modules (`ctest -L web` once installs them).
#   tools/bench/live_view.sh [--players 64] [--seconds 20] [--map foundry] [--width W --height H]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${RICOCHET_BUILD:-$root/build/release}
cmake --build "$build" --target ricochet-server ricochet-loadtest >/dev/null
if [[ ! -d $build/tests/web/node_modules ]]; then
  (cd "$build" && ctest -R '^web_npm_ci$' >/dev/null)
fi
cd "$build/tests/web"
RICOCHET_SERVER_BINARY=$build/server/ricochet-server \
RICOCHET_LOADTEST_BINARY=$build/tools/loadtest/ricochet-loadtest \
RICOCHET_SOURCE_DIR=$root \
  node live_view.bench.mjs --out "$root/tools/bench/results/live_view.jsonl" "$@"
