#!/usr/bin/env bash
# ricochet-replay on a real recording: match-bench plays a short fight on the arena and writes its
# recording; the replay matches every hash (exit 0) and exports positions; a cut file replays to
# its last whole chunk and says where it stops (exit 3), or is refused when cut in its header
# (exit 2); a flipped byte is refused with exit 2 and a message.
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
# A cut inside the ticks replays what is there and says where the file was cut short (exit 3);
# a cut inside the header is refused (exit 2). Never a crash or a mismatch.
[[ $status -eq 3 || $status -eq 2 ]]
grep -Eq 'cut short|truncated' "$dir/cut.txt"
# One byte short: the footer is cut, every tick is there and every hash checks (exit 3).
head -c $((size - 1)) "$dir/match.rcr" > "$dir/footless.rcr"
status=0; "$replay" "$dir/footless.rcr" > "$dir/footless.txt" 2>&1 || status=$?
[[ $status -eq 3 ]]
grep -Eq '^the recording was cut short: cut inside chunk [0-9]+ \(footer\) at byte [0-9]+ .*; replayable to tick [1-9][0-9]*$' "$dir/footless.txt"
grep -q '^all [1-9][0-9]* hashes match' "$dir/footless.txt"

cp "$dir/match.rcr" "$dir/flipped.rcr"
printf '\xff' | dd of="$dir/flipped.rcr" bs=1 seek=$((size / 3)) conv=notrunc status=none
status=0; "$replay" "$dir/flipped.rcr" > "$dir/flipped.txt" 2>&1 || status=$?
[[ $status -eq 2 ]]
grep -q 'CRC' "$dir/flipped.txt"
echo "replay smoke: ok"
