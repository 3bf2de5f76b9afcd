#!/usr/bin/env bash
# Smoke test of the physics study: runs every scene on its smoke sweep in this build's precision,
# merges and reports, then checks results.csv (the header, 18 fields a row, finite numbers, rows
# for every scene of `physics-study list`) and report.md; renders and checks the plots when
# gnuplot is installed (tools/deps.sh installs it).
#
#   study_smoke.sh PATH/TO/physics-study WORK_DIR
set -euo pipefail
study=$1
dir=$2
fail() {
  echo "study_smoke: FAIL: $*" >&2
  exit 1
}

rm -rf "$dir"
"$study" run --smoke --out "$dir/raw"
results=("$dir"/raw/results-*.csv)
series=("$dir"/raw/series-*.csv)
[[ -f "${results[0]}" && -f "${series[0]}" ]] || fail "run wrote no results-<precision>.csv"
"$study" report --out "$dir" --mode smoke --results "${results[@]}" --series "${series[@]}"

csv="$dir/results.csv"
header="scene,precision,variant,integrator,dt,iterations,substeps,position_correction,ccd,sleep,"
header+="metric,error,ms_per_step,steps_per_s,ms_per_sim_s,energy_drift,max_penetration,note"
[[ "$(head -n 1 "$csv")" == "$header" ]] || fail "results.csv header is '$(head -n 1 "$csv")'"

# Every row: 18 fields; dt, iterations, substeps, error, the timings, energy_drift and
# max_penetration are finite numbers (no nan, no inf); ms_per_step is positive.
awk -F, '
  NR == 1 { next }
  NF != 18 { printf "line %d has %d fields\n", NR, NF; bad = 1; next }
  {
    split("5 6 7 12 13 14 15 16 17", numeric, " ")
    for (k in numeric) {
      i = numeric[k]
      if ($i !~ /^-?[0-9]+(\.[0-9]*)?([eE][-+]?[0-9]+)?$/) {
        printf "line %d (%s): field %d is \"%s\", not a finite number\n", NR, $1, i, $i
        bad = 1
      }
    }
    if ($13 + 0 <= 0) { printf "line %d (%s): ms_per_step %s\n", NR, $1, $13; bad = 1 }
  }
  END { exit bad }' "$csv" || fail "results.csv has malformed rows"

for scene in $("$study" list); do
  grep -q "^$scene," "$csv" || fail "no rows for scene $scene"
  grep -q "^## $scene " "$dir/report.md" || fail "report.md has no section for $scene"
done
grep -q "^| scene | headline |" "$dir/report.md" || fail "report.md has no summary table"

if command -v gnuplot >/dev/null; then
  scripts=("$dir"/gnuplot/*.gp)
  [[ -f "${scripts[0]}" ]] || fail "report wrote no gnuplot scripts"
  (cd "$dir" && for script in gnuplot/*.gp; do gnuplot "$script"; done) || fail "gnuplot failed"
  for script in "${scripts[@]}"; do
    png="$dir/$(basename "${script%.gp}").png"
    [[ -s "$png" ]] || fail "$png was not drawn"
    grep -qF "($(basename "$png"))" "$dir/report.md" || fail "report.md does not embed $png"
  done
else
  echo "study_smoke: gnuplot not installed, plots not checked"
fi
echo "study_smoke: ok ($(($(wc -l <"$csv") - 1)) rows)"
