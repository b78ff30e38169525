#!/usr/bin/env bash
# Issue #9's "Done when" commands, run with one `maglev` binary, printed as the rows of a
# Markdown table (docs/performance.md keeps measured tables). Pinned to one core with
# taskset. Timings are the time loop's, from summary.json (`wall_seconds`,
# `real_time_factor`); the machine is shared, so run it when the machine is otherwise idle.
# Optional BASELINE binaries run alternately with MAGLEV in the accurate check, so a figure
# from one machine can be set beside another's (e.g. the binary of 3904763, before #9).
# Usage (from the repository root): scripts/issue-9-checks.sh MAGLEV [BASELINE ...]
set -euo pipefail
maglev=$1; shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
one=(taskset -c 0)
field() { grep -o "\"$2\": *[0-9.e+-]*" "$1/summary.json" | cut -d: -f2 | tr -d ' '; }
median() { sort -g | awk '{a[NR]=$1} END {printf "%s", a[int((NR+1)/2)]}'; }

echo "| check | measured | target |"
echo "|---|---|---|"

# 1. The accurate passage, 30 runs alternating with the baselines.
"${one[@]}" scripts/real-time-factor.sh 30 "$maglev" "$@" | while read -r line; do
  echo "| \`maglev run paper-4.2 --set scheme=accurate\`: ${line} | ≥ 200× (median) |"
done

# 2. The paper scheme at n_sub = 1000 (the bundled scenario's default), 15 runs.
for _ in $(seq 1 15); do
  rm -rf "$out/p"
  "${one[@]}" "$maglev" run paper-4.2 --out "$out/p" >/dev/null 2>&1
  field "$out/p" real_time_factor
done | median | xargs printf "| \`maglev run paper-4.2\` (paper scheme, n_sub = 1000), median of 15 | %.2f× | ≥ 5× |\n"

# 3. The 12-car forces train over 35 spans, and its growth in spans and in cars.
spans() { local s; s=$(printf '30.0,%.0s' $(seq 1 "$1")); echo "bridge.spans_m=[${s%,}]"; }
train() {
  rm -rf "$out/t"
  "${one[@]}" "$maglev" run train-forces --out "$out/t" "$@" >/dev/null 2>&1
  field "$out/t" wall_seconds
}
printf "| \`maglev run train-forces\` (12 cars, 35 spans, 5000 steps), time loop | %.3f s | ≤ 5 s |\n" "$(train)"
row=""
for n in 5 10 20 35; do row="$row $(printf '%.3f' "$(train --set "$(spans "$n")")") /"; done
echo "| the same, 5 / 10 / 20 / 35 spans (12 cars) |${row% /} s | linear |"
row=""
for n in 1 3 6 12; do row="$row $(printf '%.3f' "$(train --set train.repeat="$n")") /"; done
echo "| the same, 1 / 3 / 6 / 12 cars (35 spans) |${row% /} s | linear |"

# 4. Moving force on 3 spans, FE against the modal reference at each midspan.
dev=$(cargo test -q --release -p maglev-sim --test fe_multispan -- --nocapture 2>/dev/null |
  grep -o 'FE vs modal [0-9.]* %' | awk '{printf "%s%s", s, $4; s=" / "}')
echo "| host-sim/sim/tests/fe_multispan.rs, FE vs modal at each midspan | ${dev} % of the peak | ≤ 0.5 % |"

# 5. Bad sizes: one line on stderr, exit 2, no output directory.
bad=""
for s in elements=100000 t_end=1e12 dt=1e-12; do
  rm -rf "$out/b"
  set +e
  "$maglev" run paper-4.2 --set "$s" --out "$out/b" >/dev/null 2>"$out/err"
  rc=$?
  set -e
  lines=$(wc -l <"$out/err")
  [ -e "$out/b" ] && dir="a directory" || dir="no directory"
  bad="$bad \`$s\`: exit $rc, $lines line, $dir;"
done
echo "| \`--set\` bad sizes |${bad%;} | exit 2, one line, no directory |"
