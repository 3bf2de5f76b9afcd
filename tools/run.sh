#!/usr/bin/env bash
# The main job: installs dependencies, builds ricochet-server and runs it on embedded defaults:
# SQLite under ./data/, the sample map (server/maps/arena.toml), a TLS pair generated into ./data/
# on first start. It logs where it listens (TLS 7777, UDP 7778, admin http://127.0.0.1:9100) and
# the certificate's SHA-256 fingerprint. Ctrl-C or SIGTERM stops it gracefully (exit 0).
# Extra arguments go to the server (./tools/run.sh --help lists them; --config FILE for TOML).
#
# Sized to the machine: without --config, and unless given, it opens 8 matches of 16 players per
# core and admits 256 game clients per core (2 cores: 16 matches, 512 clients, what a 200-bot
# `ricochet-loadtest` needs). One core holds 1300-1450 bots (tools/bench/CAPACITY.md); a load
# generator on the same machine takes its share, hence the margin.
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/deps.sh
export CCACHE_DIR="${CCACHE_DIR:-$PWD/.ccache}"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
cmake --build build/release -j "$(nproc)" --target ricochet-server

given() {  # true when the server's arguments name the flag (--flag VALUE or --flag=VALUE)
  local arg
  for arg in "${@:2}"; do [[ "$arg" == "$1" || "$arg" == "$1="* ]] && return 0; done
  return 1
}
sized=()
if ! given --config "$@"; then
  cores=$(nproc)
  max_clients=$((256 * cores > 4096 ? 4096 : 256 * cores))
  matches=$((8 * cores > 256 ? 256 : 8 * cores))
  given --max-clients "$@" || sized+=(--max-clients "$max_clients")
  given --matches "$@" || sized+=(--matches "$matches")
fi
exec build/release/server/ricochet-server --data-dir data "${sized[@]}" "$@"
