#!/usr/bin/env bash
# Wall-time figure of the accurate §4.2 passage (issue #9: >= 200x real time), for one or
# more `maglev` binaries run alternately: `real_time_factor` of summary.json (the time loop
# only), N rounds, median and best per binary. The time loop is a few milliseconds, so use
# N >= 30 on a quiet machine and compare medians. docs/performance.md has measured runs.
# Usage: scripts/real-time-factor.sh N MAGLEV [MAGLEV ...]
set -euo pipefail
n=$1; shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for _ in $(seq 1 "$n"); do
  for b in "$@"; do
    rm -rf "$out/run"
    "$b" run paper-4.2 --set scheme=accurate --out "$out/run" >/dev/null 2>&1
    echo "$b $(grep -o '"real_time_factor": *[0-9.e+-]*' "$out/run/summary.json" | cut -d: -f2)"
  done
done | sort -k1,1 -k2,2n | awk '{v[$1]=v[$1]" "$2}
  END {for (b in v) {k=split(v[b],a," "); printf "%s: runs %d, median %.0fx, best %.0fx\n", b, k, a[int((k+1)/2)], a[k]}}'
