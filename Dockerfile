# Ricochet container image (Debian 12).
#   podman build -t ricochet .          (or ../shared/tools/container-check.sh from the project root)
#   podman run --rm ricochet            runs the main job: the rain scene demo with progress
#   podman run --rm ricochet physics-bench --bodies 256 --steps 60
#   podman run --rm ricochet db-bench --accounts 10000 --matches 2000   (measures this host's disk)
#   (in our sandbox `podman run` fails on setrlimit; use the script's `-- COMMAND`, which runs it with buildah)
#
# Stage 1 builds Release with CMake + Ninja; stage 2 is a slim runtime with only the binaries.
# When the server exists: add its target to RICOCHET_TARGETS, COPY its binary in the runtime stage,
# add its runtime libraries to runtime_packages, EXPOSE its ports and make it the CMD (see "server:").

############################ build stage ############################
FROM debian:bookworm AS build

# Build dependencies first, in their own layer: source edits do not reinstall packages.
# tools/deps.sh is the single list of build packages (idempotent apt-get install).
COPY tools/deps.sh /src/tools/deps.sh
RUN /src/tools/deps.sh && rm -rf /var/lib/apt/lists/*

COPY . /src
WORKDIR /src

# CMake targets to build; space separated.  server: add "ricochet-server" here.
ARG RICOCHET_TARGETS="physics-bench db-bench"
RUN cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release \
 && cmake --build build/release --target ${RICOCHET_TARGETS}

# Everything the runtime stage needs, in one place.
RUN install -D -m 0755 build/release/tools/bench/physics-bench /out/bin/physics-bench \
 && install -D -m 0755 build/release/tools/bench/db-bench /out/bin/db-bench
#   server: RUN install -D -m 0755 build/release/server/ricochet-server /out/bin/ricochet-server

############################ runtime stage ############################
FROM debian:bookworm-slim AS runtime

# Shared libraries the binaries link against beyond libc (ldd: libstdc++, libgcc_s, libm; db-bench
# also libsqlite3 and libsodium). server: add its runtime libraries here (e.g. libprotobuf32).
# Installed only if missing, so the layer needs no network while the list is already in the base.
RUN set -eu; runtime_packages="libstdc++6 libgcc-s1 libsqlite3-0 libsodium23"; missing=; \
    for p in $runtime_packages; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done; \
    if [ -n "$missing" ]; then \
      apt-get update -qq; \
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing; \
      rm -rf /var/lib/apt/lists/*; \
    fi

RUN useradd --uid 10001 --user-group --create-home --home-dir /home/ricochet \
      --shell /usr/sbin/nologin ricochet

COPY --from=build /out/bin/ /usr/local/bin/

USER ricochet:ricochet
WORKDIR /home/ricochet

# server: EXPOSE its ports here and replace the CMD with ["ricochet-server", ...].
# No ENTRYPOINT, so `podman run IMAGE physics-bench --bodies 256` runs any binary directly.
CMD ["physics-bench", "--progress"]
