#!/usr/bin/env bash
# The Java client against the C++ in one run (issue 30's bench): the snapshot decoders on the
# same recorded streams (tests/vectors/snapshots_spheres901.txt, _players64.txt), C++ and Java
# alternating --repeat times per scene, then a ratio line per scene (medians of the runs; the bar
# is Java <= 2x C++ per snapshot and 0 bytes allocated per warm snapshot), then a whole Java
# client's CPU per second of play at 60 Hz against a real ricochet-server started here on
# 127.0.0.1. JSON Lines, appended to tools/bench/results/java_decode.jsonl.
#
#   tools/bench/java_decode.sh [--repeat 3] [--rounds 200] [--warmup-rounds 100]
#                              [--client-seconds 20] [--build build/release] [--out FILE]
#   tools/bench/java_decode.sh --smoke [--build DIR]   # a few rounds, 2 s of play, lines checked,
#                                                       # nothing kept (ctest java_bench_smoke)
#
# Build first: cmake --build build/release --target snapshot-decode-bench ricochet_java_bench
#   ricochet_client_jar ricochet-server
set -euo pipefail
cd "$(dirname "$0")/../.."
repeat=3
rounds=200
warmup=100
client_seconds=20
build=build/release
out=tools/bench/results/java_decode.jsonl
smoke=0
while (($#)); do
  case "$1" in
    --repeat) repeat=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --warmup-rounds) warmup=$2; shift 2 ;;
    --client-seconds) client_seconds=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --smoke) smoke=1; shift ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
tmp=$(mktemp -d)
server_pid=
cleanup() {
  if [[ -n $server_pid ]]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
if ((smoke)); then
  repeat=1 rounds=2 warmup=1 client_seconds=2 out=$tmp/smoke.jsonl
fi

jars=/usr/share/java
class_path=$build/tools/bench/java/ricochet-java-bench.jar
class_path+=:$(ls "$build"/clients/java/dist/ricochet-client-*.jar | head -n 1)
class_path+=:$jars/protobuf.jar:$jars/bcprov.jar:$jars/bctls.jar:$jars/bcutil.jar
cpp_bench=$build/tools/bench/snapshot-decode-bench
server=$build/server/ricochet-server
for file in "$cpp_bench" "$server" ${class_path//:/ }; do
  [[ -e $file ]] || { echo "java_decode.sh: $file is missing (build it first)" >&2; exit 2; }
done

: >"$tmp/run.jsonl"
for scene in spheres901 players64; do
  vectors=tests/vectors/snapshots_$scene.txt
  for ((i = 0; i < repeat; ++i)); do
    "$cpp_bench" --vectors "$vectors" --rounds "$rounds" --warmup-rounds "$warmup" >>"$tmp/run.jsonl"
    java -cp "$class_path" io.ricochet.bench.SnapshotDecodeBench --vectors "$vectors" \
      --rounds "$rounds" --warmup-rounds "$warmup" >>"$tmp/run.jsonl"
  done
  # Medians of the repeats (nearest rank, the lower middle of an even count), then Java / C++.
  jq -cs --arg scene "$scene" --argjson repeat "$repeat" '
    def median: sort | .[((length + 1) / 2 | ceil) - 1];
    [.[] | select(.bench == "snapshot_decode" and .scene == $scene)] as $lines
    | ($lines | map(select(.lang == "cpp"))) as $cpp
    | ($lines | map(select(.lang == "java"))) as $java
    | (($java | map(.decode_us) | median) / ($cpp | map(.decode_us) | median)) as $mean_ratio
    | {bench: "snapshot_decode_ratio", scene: $scene, repeat: $repeat,
       java_over_cpp_decode_us: ($mean_ratio * 1000 | round / 1000),
       java_over_cpp_p50: (($java | map(.decode_us_p50) | median)
                           / ($cpp | map(.decode_us_p50) | median) * 1000 | round / 1000),
       java_over_cpp_cpu: (($java | map(.cpu_us_per_snapshot) | median)
                           / ($cpp | map(.cpu_us_per_snapshot) | median) * 1000 | round / 1000),
       java_allocated_bytes_per_snapshot: ($java | map(.allocated_bytes_per_snapshot) | max),
       within_2x: ($mean_ratio <= 2),
       zero_allocation: (($java | map(.allocated_bytes_per_snapshot) | max) == 0)}
  ' "$tmp/run.jsonl" >>"$tmp/run.jsonl"
done

if ((client_seconds > 0)); then
  # The server as tests/clients/java's ServerProcess runs it: loopback, ports 0, the sample arena.
  mkdir -p "$tmp/server"
  cat >"$tmp/server/server.toml" <<TOML
[server]
data_dir = "$tmp/server/data"
ports_file = "$tmp/server/ports.json"
threads = 2
shutdown_grace_s = 2
[control]
bind = "127.0.0.1"
port = 0
[game]
bind = "127.0.0.1"
port = 0
[admin]
bind = "127.0.0.1"
port = 0
[matches]
count = 1
max_players = 16
maps = ["$PWD/server/maps/arena.toml"]
seed = 42
warmup_s = 0
frag_limit = 0
record = false
min_players = 1
time_limit_s = 3600
[db]
password_hashing = "minimum"
TOML
  "$server" --config "$tmp/server/server.toml" >"$tmp/server/log" 2>&1 &
  server_pid=$!
  for ((i = 0; i < 300; ++i)); do
    jq -e .fingerprint "$tmp/server/ports.json" >/dev/null 2>&1 && break
    kill -0 "$server_pid" 2>/dev/null || { cat "$tmp/server/log" >&2; exit 1; }
    sleep 0.1
  done
  port=$(jq -r .control_port "$tmp/server/ports.json")
  pin=$(jq -r .fingerprint "$tmp/server/ports.json")
  java -cp "$class_path" io.ricochet.bench.ClientCpuBench --host 127.0.0.1 --control-port "$port" \
    --pin "$pin" --seconds "$client_seconds" --rate 60 >>"$tmp/run.jsonl"
fi

# Every line one JSON object with its bench's fields.
jq -e -s '
  all(.[]; type == "object" and (.bench | type) == "string")
  and all(.[] | select(.bench == "snapshot_decode");
          (.decode_us | type) == "number" and .refused == 0)
  and (map(select(.bench == "snapshot_decode_ratio")) | length) == 2
  and all(.[] | select(.bench == "snapshot_decode_ratio"); (.java_over_cpp_decode_us | type) == "number")
' "$tmp/run.jsonl" >/dev/null || { echo "java_decode.sh: bad result lines:" >&2; cat "$tmp/run.jsonl" >&2; exit 1; }
if ((client_seconds > 0)); then
  jq -e -s 'map(select(.bench == "java_client_cpu")) | length == 1 and (.[0].process_cpu_ms_per_s | type) == "number"' \
    "$tmp/run.jsonl" >/dev/null || { echo "java_decode.sh: no client line" >&2; cat "$tmp/run.jsonl" >&2; exit 1; }
fi
cat "$tmp/run.jsonl"
cat "$tmp/run.jsonl" >>"$out"
