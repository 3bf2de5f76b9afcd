#!/usr/bin/env bash
# ricochet-replay on a real recording: match-bench plays a short fight on the arena and writes its
# recording; the replay matches every hash (exit 0) and exports positions; a cut file and a
# flipped byte are refused with exit 2 and a message.
set -euo pipefail
bench=$1 replay=$2 map=$3 dir=$4
rm -rf "$dir" && mkdir -p "$dir"
"$bench" --players 4 --seconds 1 --lag-shots 2000 --map "$map" --record "$dir/match.rcr" > "$dir/bench.jsonl"
grep -q '"replay_hashes_match":true' "$dir/bench.jsonl"
"$replay" "$dir/match.rcr" --export "$dir/positions.csv" | tee "$dir/replay.txt"
grep -q '^all [1-9][0-9]* hashes match' "$dir/replay.txt"
head -1 "$dir/positions.csv" | grep -q '^tick,entity,x,y,z$'
[[ $(wc -l < "$dir/positions.csv") -gt 100 ]]
"$replay" --json "$dir/match.rcr" | grep -q '"first_mismatch_tick":null'

size=$(stat -c %s "$dir/match.rcr")
head -c $((size / 2)) "$dir/match.rcr" > "$dir/cut.rcr"
status=0; "$replay" "$dir/cut.rcr" > "$dir/cut.txt" 2>&1 || status=$?
# A cut inside the ticks replays what is there and says the file was cut short (exit 0); a cut
# inside the header is refused (exit 2). Never a crash or a mismatch.
[[ $status -eq 0 || $status -eq 2 ]]
grep -Eq 'cut short|truncated' "$dir/cut.txt"

cp "$dir/match.rcr" "$dir/flipped.rcr"
printf '\xff' | dd of="$dir/flipped.rcr" bs=1 seek=$((size / 3)) conv=notrunc status=none
status=0; "$replay" "$dir/flipped.rcr" > "$dir/flipped.txt" 2>&1 || status=$?
[[ $status -eq 2 ]]
grep -q 'CRC' "$dir/flipped.txt"
echo "replay smoke: ok"
