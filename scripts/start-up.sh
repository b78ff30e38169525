#!/usr/bin/env bash
# Start-up against time loop of `maglev run paper-4.2 --set scheme=accurate` (issue #24: the
# whole process at most 3x its time loop), for one or more `maglev` binaries run alternately
# on one core (`taskset -c 0`): the whole process's wall time and the time loop's
# (`wall_seconds` of summary.json), N rounds, medians and their ratio per binary. The
# instruction counts (callgrind) are in docs/performance.md with their commands.
# Usage: scripts/start-up.sh N MAGLEV [MAGLEV ...]
set -euo pipefail
n=$1; shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for _ in $(seq 1 "$n"); do
  for b in "$@"; do
    rm -rf "$out/run"
    t0=$(date +%s%N)
    taskset -c 0 "$b" run paper-4.2 --set scheme=accurate --out "$out/run" >/dev/null 2>&1
    t1=$(date +%s%N)
    loop=$(grep -o '"wall_seconds": *[0-9.e+-]*' "$out/run/summary.json" | cut -d: -f2)
    echo "$b $(( (t1 - t0) / 1000 )) $loop"
  done
done | python3 -c '
import sys, statistics as st
runs = {}
for line in sys.stdin:
    b, whole_us, loop_s = line.split()
    runs.setdefault(b, []).append((int(whole_us) * 1e-6, float(loop_s)))
for b, r in runs.items():
    whole = st.median(w for w, _ in r)
    loop = st.median(l for _, l in r)
    print(f"{b}: runs {len(r)}, whole process median {whole * 1e3:.1f} ms, time loop median {loop * 1e3:.2f} ms, ratio {whole / loop:.1f}")
'
