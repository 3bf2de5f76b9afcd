#!/usr/bin/env bash
# Installs exactly the Debian 12 packages Ricochet needs to build, test and run.
# Idempotent: checks each package with dpkg -s and only then runs apt-get update (once) and install.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev      # physics math
  libsqlite3-dev     # the embedded database (db/)
  libpq-dev          # the PostgreSQL store's client library, libpq 15 (db/)
  postgresql-15      # the real PostgreSQL cluster the db tests start (initdb + pg_ctl)
  libsodium-dev      # Argon2id password hashing and session tokens (db/)
  libgtest-dev       # unit and integration tests
  libcli11-dev       # command-line parsing for the server and the tools
  libboost1.81-dev   # Asio 1.26 and Beast (server/); never libboost-dev, which is 1.74 and conflicts
  libprotobuf-dev protobuf-compiler  # the wire messages (proto/)
  libssl-dev         # TLS 1.3 for the control channel (asio::ssl over OpenSSL 3)
  libspdlog-dev      # the server's logs (text or JSON lines)
  libtomlplusplus-dev # the server's config file
  gnuplot-nox        # plots of the physics study (tools/physics-study)
  clang-format       # the formatter; tools/test.sh checks the tree against .clang-format
  clang-16           # the sanitized builds of tools/test.sh and the libFuzzer targets (tools/fuzz.sh)
  lld-16             # their linker (links the sanitized binaries in less than half of bfd's time)
  libclang-rt-16-dev # their sanitizer and fuzzer runtimes
  openjdk-17-jdk-headless  # the Java client library (clients/java), built for Java 8 / Android
  libprotobuf-java         # its messages' runtime (3.21.12, the same as protoc)
  libbcprov-java libbctls-java libbcutil-java  # its ChaCha20-Poly1305 and TLS 1.3 (Bouncy Castle)
  junit5                   # its tests
  jq                       # tools/bench/java_decode.sh (its ratio lines and smoke test)
  prometheus python3-yaml  # tests/deploy: promtool checks /metrics and deploy/prometheus; YAML of deploy/
  chromium                 # tests/web: the dashboard in a real browser (headless, driven by playwright-core)
)
# The optional peer benchmark (Bullet, ODE) needs two more; ask for them with RICOCHET_PEERS=1.
if [[ "${RICOCHET_PEERS:-0}" == 1 ]]; then
  packages+=(libbullet-dev libode-dev)
fi

missing=()
for package in "${packages[@]}"; do
  dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "deps.sh: installing ${missing[*]}"
if [[ $(id -u) -ne 0 ]]; then sudo=sudo; else sudo=; fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
