#!/usr/bin/env bash
# Benchmark (not a test): the 100-run seed sweep of paper-4.2 (accurate scheme) with --jobs 1
# and with --jobs 2, ROUNDS times alternately (default 5). Prints each round's wall times and
# ratio with the load average, then the median ratio and the ratio of the best walls, and
# checks that every results.csv is byte-identical to the first.
# Usage: bash host-sim/cli/sweeps/bench.sh [OUT_DIR]   (env: ROUNDS, MAGLEV)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-target/sweep-bench}
rounds=${ROUNDS:-5}
maglev=${MAGLEV:-target/release/maglev}
[ -x "$maglev" ] || cargo build --release -q -p maglev
rm -rf "$out" && mkdir -p "$out"
echo "$(nproc) cores; $rounds rounds; load average (1, 5, 15 min) before each round"
now() { date +%s.%N; }
rows=""
for r in $(seq 1 "$rounds"); do
  load=$(cut -d' ' -f1 /proc/loadavg)
  t0=$(now)
  "$maglev" sweep host-sim/cli/sweeps/seeds-100.toml --jobs 1 --out "$out/jobs1-$r" 2>/dev/null
  t1=$(now)
  "$maglev" sweep host-sim/cli/sweeps/seeds-100.toml --jobs 2 --out "$out/jobs2-$r" 2>/dev/null
  t2=$(now)
  cmp "$out/jobs1-1/results.csv" "$out/jobs1-$r/results.csv"
  cmp "$out/jobs1-1/results.csv" "$out/jobs2-$r/results.csv"
  row=$(awk -v a="$t0" -v b="$t1" -v c="$t2" -v l="$load" -v r="$r" 'BEGIN {
    printf "%d %s %.3f %.3f %.3f", r, l, b - a, c - b, (c - b) / (b - a) }')
  echo "round $row" | awk '{ printf "round %s: load %s, --jobs 1 %.2f s, --jobs 2 %.2f s, ratio %.3f\n", $2, $3, $4, $5, $6 }'
  rows="$rows$row"$'\n'
done
echo "results.csv byte-identical in all $((2 * rounds)) sweeps"
printf '%s' "$rows" | sort -k5 -g | awk -v n="$rounds" '
  { ratio[NR] = $5; if (NR == 1 || $3 < s) s = $3; if (NR == 1 || $4 < p) p = $4 }
  END {
    m = (n % 2) ? ratio[(n + 1) / 2] : (ratio[n / 2] + ratio[n / 2 + 1]) / 2
    printf "median ratio %.3f; best walls %.2f s / %.2f s, ratio %.3f (target <= 0.6)\n", m, s, p, p / s }'
