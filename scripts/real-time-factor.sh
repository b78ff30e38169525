#!/usr/bin/env bash
# Wall-time figures of the accurate §4.2 passage, for one or more `maglev` binaries run
# alternately: `real_time_factor` of summary.json (the time loop only; issue #9: >= 200x),
# N rounds, median and best per binary; and the whole process's wall time against the time
# loop's (`wall_seconds`), medians (issue #24: start-up at most 3x the loop). The time loop is
# a few milliseconds, so use N >= 30 on a quiet machine and compare medians; prefix with
# `taskset -c 0` for one core. docs/performance.md has measured runs.
# Usage: scripts/real-time-factor.sh N MAGLEV [MAGLEV ...]
set -euo pipefail
n=$1; shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { grep -o "\"$2\": *[0-9.e+-]*" "$1/summary.json" | cut -d: -f2; }
for _ in $(seq 1 "$n"); do
  for b in "$@"; do
    rm -rf "$out/run"
    t0=$(date +%s%N)
    "$b" run paper-4.2 --set scheme=accurate --out "$out/run" >/dev/null 2>&1
    t1=$(date +%s%N)
    echo "$b $(field "$out/run" real_time_factor) $(field "$out/run" wall_seconds) $(( (t1 - t0) / 1000 ))"
  done
done | python3 -c '
import sys, statistics as st
runs = {}
for line in sys.stdin:
    b, rtf, loop_s, whole_us = line.split()
    runs.setdefault(b, []).append((float(rtf), float(loop_s), int(whole_us) * 1e-6))
for b, r in runs.items():
    loop, whole = st.median(x[1] for x in r), st.median(x[2] for x in r)
    print(f"{b}: runs {len(r)}, median {st.median(x[0] for x in r):.0f}x, best {max(x[0] for x in r):.0f}x;"
          f" whole process median {whole * 1e3:.1f} ms, {whole / loop:.1f}x the loop")
'
