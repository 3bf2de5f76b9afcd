#!/usr/bin/env bash
# The capacity benchmark (tools/bench/CAPACITY.md): one ricochet-server --threads 1 pinned to core
# 0, ricochet-loadtest pinned to core 1, matches of 16 on foundry.toml (the large map), 60 Hz
# ticks and snapshots, bots fighting; a sweep of bot counts. Each step's figures go to
# DIR/report.json and are appended, one JSON line per step, to tools/bench/results/capacity.jsonl.
# The capacity is the largest step with server tick p99 <= 4 ms, no overrun, snapshot loss <= 1 %,
# the server's core not saturated and every bot connected (report.json "capacity_bots").
#
#   tools/bench/capacity.sh [--sweep 100,200,400] [--duration 60s] [--out DIR] [--build DIR]
#                           [--server-bin PATH] [--server-arg ARG]... [--nice N | --rt] [--perf]
#                           [--no-append] [-- extra ricochet-loadtest options]
#
# --server-arg passes one more flag to ricochet-server (repeat it for each word), e.g.
# `--server-arg --snapshot-cache-off --server-arg streams` to measure a snapshot cache layer.
# --nice N (root, e.g. -10) runs both at that niceness: on a machine where others compile, the
# pinned server and generator then get the CPU they ask for instead of a fair share with the
# compilers (their CPU time is measured either way; their tick times are not comparable
# otherwise).
# --rt (root) runs both under SCHED_FIFO priority 1 instead: nothing at normal priority preempts
# them mid-tick (a preempted tick's wall time is the preemption's), and the kernel's RT throttle
# (sched_rt_runtime_us) still leaves the other work 5 % of each core should one saturate.
# --server-bin runs another ricochet-server binary (an A/B against an older build).
# --perf also records `perf stat` of the server over the whole run (syscalls per second, context
# switches) into DIR/perf-stat.txt. Needs a machine with 2 or more cores.
set -euo pipefail
cd "$(dirname "$0")/../.."

invocation=("$@")
loadavg="$(cut -d' ' -f1-3 /proc/loadavg)"
sweep="100,200,400,600,800,1000"
duration="60s"
out=""
build="build/release"
server_bin=""
niceness=0
priority=()
perf=0
append=1
extra=()
server_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --sweep) sweep="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --server-bin) server_bin="$2"; shift 2 ;;
    --server-arg) server_args+=("$2"); shift 2 ;;
    --nice) niceness="$2"; shift 2 ;;
    --rt) priority=(chrt -f 1); shift ;;
    --perf) perf=1; shift ;;
    --no-append) append=0; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "capacity.sh: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
if ! [[ "$niceness" =~ ^-?[0-9]+$ ]]; then
  echo "capacity.sh: --nice must be an integer (-20..19), got '$niceness'" >&2
  exit 2
fi
if ! [[ "$sweep" =~ ^[0-9]+(,[0-9]+)*$ ]]; then
  echo "capacity.sh: --sweep must be bot counts separated by commas, got '$sweep'" >&2
  exit 2
fi
[[ -n "$server_bin" ]] || server_bin="$build/server/ricochet-server"
loadtest_bin="$build/tools/loadtest/ricochet-loadtest"
for binary in "$server_bin" "$loadtest_bin"; do
  [[ -x "$binary" ]] || { echo "capacity.sh: $binary missing: cmake --build $build --target ricochet-server ricochet-loadtest" >&2; exit 2; }
done
if [[ $(nproc) -lt 2 ]]; then
  echo "capacity.sh: needs 2 cores (server on core 0, generator on core 1), found $(nproc)" >&2
  exit 2
fi
# The machine's speed now: a shared VM's varies by half over minutes, which moves the capacity
# as much. A 16-player match's mean tick (match-bench, thread CPU time, pinned to core 0) before
# the server starts goes into every line, so that sweeps are compared at the same speed.
calibration="null"
if [[ -x "$build/tools/bench/match-bench" ]]; then
  calibration=$(taskset -c 0 "$build/tools/bench/match-bench" --players 16 --seconds 5 \
                  --lag-shots 1000 --clock thread-cpu --map server/maps/foundry.toml 2>/dev/null |
                grep -o '"tick_ms_avg":[0-9.]*' | head -1 | cut -d: -f2)
  [[ -n "$calibration" ]] || calibration="null"
  echo "capacity.sh: machine speed: a 16-player match ticks in $calibration ms on average" >&2
fi
# The match tick does not time what dominates the server's core at capacity: the kernel's UDP
# and epoll, the AEAD, memcpy (CAPACITY.md, 2026-12-06). A game datagram out of core 0 and its
# answer back from core 1 (loopback-bench: sealed, sendmmsg/recvmmsg, the server thread's CPU
# µs per datagram, median of its rounds) goes into every line beside it.
calibration_loopback="null"
if [[ -x "$build/tools/bench/loopback-bench" ]]; then
  calibration_loopback=$(taskset -c 0,1 "$build/tools/bench/loopback-bench" --cores 0,1 \
                           --seconds 3 2>/dev/null |
                         grep -o '"cpu_us_per_datagram_p50":[0-9.]*' | head -1 | cut -d: -f2 ||
                         true)
  [[ -n "$calibration_loopback" ]] || calibration_loopback="null"
  echo "capacity.sh: machine speed: a datagram through loopback costs core 0 $calibration_loopback µs (median)" >&2
fi
largest="${sweep##*,}"
matches=$(( (largest + 15) / 16 ))
[[ -n "$out" ]] || out="$(mktemp -d /tmp/ricochet-capacity-XXXXXX)"
mkdir -p "$out"
data="$(mktemp -d /tmp/ricochet-capacity-data-XXXXXX)"
server_pid=""
perf_pid=""
cleanup() {
  [[ -n "$perf_pid" ]] && kill -INT "$perf_pid" 2>/dev/null && wait "$perf_pid" 2>/dev/null || true
  if [[ -n "$server_pid" ]]; then
    kill -TERM "$server_pid" 2>/dev/null || true
    wait "$server_pid" 2>/dev/null || true
  fi
  rm -rf "$data"
}
trap cleanup EXIT

# Loopback only; every port chosen free by the kernel. The login hashing is at its minimum cost
# (db.password_hashing: a load test's thousands of sign-ins are not what is measured); every
# other limit is the server's default but the game client count, raised to fit the sweep.
nice -n "$niceness" "${priority[@]}" taskset -c 0 "$server_bin" --data-dir "$data" --threads 1 \
  --control-bind 127.0.0.1 --control-port 0 --game-bind 127.0.0.1 --game-port 0 \
  --admin-bind 127.0.0.1 --admin-port 0 --ports-file ports.json \
  --matches "$matches" --match-max-players 16 --max-clients 4096 \
  --maps server/maps/foundry.toml --tick-rate-hz 60 --snapshot-rate-hz 60 \
  --time-limit-s 0 --frag-limit 0 --warmup-s 0 --password-hashing minimum \
  --log-level info "${server_args[@]}" > "$out/server.log" 2>&1 &
server_pid=$!

# The bound ports and the fingerprint come from the ports file, written once it listens.
ports=""
for _ in $(seq 1 100); do
  ports=$(cat "$data/ports.json" 2>/dev/null || true)
  [[ -n "$ports" ]] && break
  kill -0 "$server_pid" 2>/dev/null || { echo "capacity.sh: the server exited; see $out/server.log" >&2; exit 1; }
  sleep 0.1
done
if [[ -z "$ports" ]]; then
  echo "capacity.sh: no ports file from the server in 10 s; see $out/server.log" >&2
  exit 1
fi
control_port=$(sed -E 's/.*"control_port":([0-9]+).*/\1/' <<<"$ports")
admin_port=$(sed -E 's/.*"admin_port":([0-9]+).*/\1/' <<<"$ports")
fingerprint=$(sed -E 's/.*"fingerprint":"([0-9A-F:]+)".*/\1/' <<<"$ports")

if [[ $perf -eq 1 ]]; then
  perf stat -e task-clock,context-switches,cpu-migrations,raw_syscalls:sys_enter \
    -p "$server_pid" -o "$out/perf-stat.txt" &
  perf_pid=$!
fi

echo "capacity.sh: server pid $server_pid on core 0 ($matches matches of 16), generator on core 1, sweep $sweep, out $out" >&2
# The generator's heap in transparent huge pages: its thousands of bots' decoders and
# connections span some 300 MB read at random, and on a VM every TLB miss is a two-level page
# walk. Measured at 800 bots: 6-10 % less of its core (tools/bench/CAPACITY.md). glibc reads this at
# start; the server is run as an operator would run it, without.
GLIBC_TUNABLES="glibc.malloc.hugetlb=1${GLIBC_TUNABLES:+:$GLIBC_TUNABLES}" \
  nice -n "$niceness" "${priority[@]}" taskset -c 1 "$loadtest_bin" --server 127.0.0.1 --port "$control_port" --admin-port "$admin_port" \
  --fingerprint "$fingerprint" --server-pid "$server_pid" --match-size 16 \
  --sweep "$sweep" --duration "$duration" --out "$out" "${extra[@]}"

if [[ -n "$perf_pid" ]]; then
  kill -INT "$perf_pid" 2>/dev/null || true
  wait "$perf_pid" 2>/dev/null || true
  perf_pid=""
fi
if [[ $append -eq 1 ]]; then
  # Each line also says how it was run: this script's options, the commit, the machine's load.
  mkdir -p tools/bench/results
  script="tools/bench/capacity.sh ${invocation[*]}"
  script="${script//\"/}"
  sed "s|^{|{\"script\":\"$script\",\"git\":\"$(git rev-parse --short HEAD)\",\"loadavg_at_start\":\"$loadavg\",\"calibration_match_tick_ms_avg\":$calibration,\"calibration_loopback_cpu_us_p50\":$calibration_loopback,\"nproc\":$(nproc),|" \
    "$out/steps.jsonl" >> tools/bench/results/capacity.jsonl
fi
grep -o '"capacity_bots":[0-9]*' "$out/report.json" >&2
echo "capacity.sh: report $out/report.json, plots $out/*.png" >&2
