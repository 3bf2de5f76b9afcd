#!/usr/bin/env bash
# The main job. Until the server exists it runs the physics demo: the rain scene with a progress
# line and final statistics. Extra arguments go to physics-bench (e.g. --bodies 16384).
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
export CCACHE_DIR="${CCACHE_DIR:-$PWD/.ccache}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
cmake --build build/release -j "$(nproc)" --target physics-bench
exec build/release/tools/bench/physics-bench --progress "$@"
