# Ricochet container image (Debian 12): the game server.
#   podman build -t ricochet .          (or ../shared/tools/container-check.sh from the project root)
#   podman run -p 7777:7777/tcp -p 7778:7778/udp -p 9100:9100/tcp -v ricochet-data:/var/lib/ricochet ricochet
#   podman run --rm ricochet ricochet-server --help        (every option and its default)
#   podman run --rm ricochet physics-bench --bodies 256 --steps 60
#   podman run --rm --network host ricochet ricochet-bot --port 7777 --trust-file /tmp/fp --bots 8
#   podman run --rm -v ricochet-data:/var/lib/ricochet ricochet ricochet-replay FILE
#   (in our sandbox `podman run` fails on setrlimit; use the script's `-- COMMAND`, which runs it with buildah)
#
# Stage 1 builds Release with CMake + Ninja; stage 2 is a slim runtime with only the binaries (the
# server, the bot, the replayer, two benches), the sample maps and the runtime libraries they
# link against.

############################ build stage ############################
FROM debian:bookworm AS build

# Build dependencies first, in their own layer: source edits do not reinstall packages.
# tools/deps.sh is the single list of build packages (idempotent apt-get install).
COPY tools/deps.sh /src/tools/deps.sh
RUN /src/tools/deps.sh && rm -rf /var/lib/apt/lists/*

COPY . /src
WORKDIR /src

# CMake targets to build; space separated.
ARG RICOCHET_TARGETS="ricochet-server ricochet-bot ricochet-replay physics-bench db-bench"
RUN cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release \
 && cmake --build build/release --target ${RICOCHET_TARGETS}

# Everything the runtime stage needs, in one place.
RUN install -D -m 0755 build/release/server/ricochet-server /out/bin/ricochet-server \
 && install -D -m 0755 build/release/tools/bot/ricochet-bot /out/bin/ricochet-bot \
 && install -D -m 0755 build/release/tools/replay/ricochet-replay /out/bin/ricochet-replay \
 && install -D -m 0755 build/release/tools/bench/physics-bench /out/bin/physics-bench \
 && install -D -m 0755 build/release/tools/bench/db-bench /out/bin/db-bench \
 && install -D -m 0644 -t /out/share/ricochet/maps \
      server/maps/arena.toml server/maps/foundry.toml server/maps/foundry_ramps.obj \
 && install -D -m 0644 server/config/ricochet.toml /out/share/ricochet/ricochet.toml

############################ runtime stage ############################
FROM debian:bookworm-slim AS runtime

# Shared libraries the binaries link against beyond libc (ldd of ricochet-server): libstdc++,
# libgcc_s; SQLite, libpq (PostgreSQL, db.url) and libsodium (db/, the game channel's crypto);
# protobuf 3.21 (the wire messages); OpenSSL 3 (TLS 1.3); spdlog and fmt (logs); toml++ (the
# config file). apt brings their own dependencies (zlib for protobuf, Kerberos and LDAP for
# libpq). Same Debian packages as tools/deps.sh's -dev ones.
# Installed only if missing, so the layer needs no network while the list is already in the base.
RUN set -eu; runtime_packages="libstdc++6 libgcc-s1 libsqlite3-0 libpq5 libsodium23 libprotobuf32 \
      libssl3 libspdlog1.10 libfmt9 libtomlplusplus3"; missing=; \
    for p in $runtime_packages; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done; \
    if [ -n "$missing" ]; then \
      apt-get update -qq; \
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing; \
      rm -rf /var/lib/apt/lists/*; \
    fi

# A non-root user owns the data directory (SQLite database, generated TLS pair) and the mount
# point of a results outbox shared by several servers (deploy/: a volume made there takes its
# owner from it).
RUN useradd --uid 10001 --user-group --create-home --home-dir /home/ricochet \
      --shell /usr/sbin/nologin ricochet \
 && install -d -o ricochet -g ricochet -m 0700 /var/lib/ricochet /var/lib/ricochet-outbox

COPY --from=build /out/bin/ /usr/local/bin/
COPY --from=build /out/share/ricochet/ /usr/local/share/ricochet/

USER ricochet:ricochet
WORKDIR /home/ricochet
VOLUME ["/var/lib/ricochet"]

# Control channel (TLS over TCP), game channel (UDP), admin HTTP (/metrics, /healthz, /readyz).
EXPOSE 7777/tcp 7778/udp 9100/tcp

# /healthz answers 200 while every match ticks on time. The slim base has no curl; bash's
# /dev/tcp sends the request and `read -t` bounds the wait for the status line.
# (Docker-format images only: podman's default OCI format ignores HEALTHCHECK with a warning;
# build with `--format docker` to keep it.)
HEALTHCHECK --interval=15s --timeout=5s --start-period=20s --retries=3 \
  CMD ["bash", "-c", "exec 3<>/dev/tcp/127.0.0.1/9100 && printf 'GET /healthz HTTP/1.1\\r\\nHost: 127.0.0.1\\r\\nConnection: close\\r\\n\\r\\n' >&3 && read -r -t 4 status <&3 && [[ $status == 'HTTP/1.1 200 '* ]]"]

# The admin port listens on the container's loopback only (the HEALTHCHECK above reaches it). To
# scrape /metrics from outside, add `--admin-bind 0.0.0.0 --admin-token-file FILE` (a secret
# mounted into the container; Prometheus sends it as a bearer token) and publish 9100 only where
# Prometheus runs. Any flag can be added after the image name's command, or a file given with
# --config (the documented sample is /usr/local/share/ricochet/ricochet.toml).
# No ENTRYPOINT, so `podman run IMAGE physics-bench --bodies 256` runs any binary directly.
CMD ["ricochet-server", "--data-dir", "/var/lib/ricochet", \
     "--maps", "/usr/local/share/ricochet/maps/arena.toml,/usr/local/share/ricochet/maps/foundry.toml"]
