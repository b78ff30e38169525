#!/usr/bin/env bash
# Benchmark (not a test): the 100-run seed sweep of paper-4.2 (accurate scheme) with --jobs 1
# and with --jobs 2, wall times, their ratio, the machine's load before and after, and a check
# that both results.csv are byte-identical. Usage: bash host-sim/sweeps/bench.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-target/sweep-bench}
maglev=${MAGLEV:-target/release/maglev}
[ -x "$maglev" ] || cargo build --release -q -p maglev-host-sim
rm -rf "$out" && mkdir -p "$out"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min) on $(nproc) cores"
TIMEFORMAT='  (bash time: %R s wall, %U s user, %S s sys)'
t0=$(date +%s.%N)
time "$maglev" sweep host-sim/sweeps/seeds-100.toml --jobs 1 --out "$out/jobs1"
t1=$(date +%s.%N)
echo "load between: $(cut -d' ' -f1-3 /proc/loadavg)"
time "$maglev" sweep host-sim/sweeps/seeds-100.toml --jobs 2 --out "$out/jobs2"
t2=$(date +%s.%N)
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
cmp "$out/jobs1/results.csv" "$out/jobs2/results.csv"
awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN {
  s = b - a; p = c - b
  printf "serial (--jobs 1): %.2f s, parallel (--jobs 2): %.2f s, ratio %.3f (target <= 0.6)\n", s, p, p / s }'
