#!/usr/bin/env bash
# The main job: installs dependencies, builds ricochet-server and runs it on embedded defaults:
# SQLite under ./data/, the sample map (server/maps/arena.toml), a TLS pair generated into ./data/
# on first start. It logs where it listens (TLS 7777, UDP 7778, admin http://127.0.0.1:9100) and
# the certificate's SHA-256 fingerprint. Ctrl-C or SIGTERM stops it gracefully (exit 0).
# Extra arguments go to the server (./tools/run.sh --help lists them; --config FILE for TOML).
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
export CCACHE_DIR="${CCACHE_DIR:-$PWD/.ccache}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
cmake --build build/release -j "$(nproc)" --target ricochet-server
exec build/release/server/ricochet-server --data-dir data "$@"
