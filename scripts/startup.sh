#!/usr/bin/env bash
# Where the whole process of `maglev run paper-4.2 --set scheme=accurate` spends its CPU time
# (issue #24: at most 3x its time loop), for one or more `maglev` binaries run alternately.
# Each row adds one part to the one above: exec and the runtime (`--version`), reading the
# case (a run refused at an unknown key), the output directory and its files (a rigid
# guideway, one step, no irregularity), the FE span's set-up (the modal basis), the two
# irregularity tables, and the full 500 steps with their outputs. Per row: CPU time
# (perf's task-clock, user + system, mean of 10 runs; the median and the least of R such
# means) and page faults; then the time loop's own wall time (summary.json `wall_seconds` of
# the last whole run of each round; on a busy machine the least is the one to read).
# Needs `perf`. Prefix with `taskset -c 0` for one core. docs/performance.md has a measured run.
# Usage: scripts/startup.sh R MAGLEV [MAGLEV ...]
set -euo pipefail
rounds=$1; shift
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
base=(run paper-4.2 --set scheme=accurate)
one=(--set t_end=0.001)
rows=(
  "exec + runtime|--version"
  "+ case read|${base[*]} --set no_such_key=1"
  "+ output (rigid, 1 step)|${base[*]} ${one[*]} --set irregularity.enabled=false --set model=rigid"
  "+ FE span set-up|${base[*]} ${one[*]} --set irregularity.enabled=false"
  "+ irregularity tables|${base[*]} ${one[*]}"
  "+ 500 steps (whole run)|${base[*]}"
)
for _ in $(seq 1 "$rounds"); do
  for b in "$@"; do
    for row in "${rows[@]}"; do
      name=${row%%|*} args=${row#*|}
      # shellcheck disable=SC2086
      stat=$({ perf stat -x, -r 10 -e task-clock,page-faults "$b" $args --out "$out/run" 2>&1 >/dev/null ||
        true; } | grep -E 'task-clock|page-faults' | cut -d, -f1 | tr '\n' ' ')
      echo "$b|$name|$stat"
    done
    wall=$(grep -o '"wall_seconds": *[0-9.e+-]*' "$out/run/summary.json" | cut -d: -f2)
    echo "$b|time loop (wall_seconds)|$(python3 -c "print($wall * 1e3)") 0"
  done
done | python3 -c '
import sys, statistics as st
rows = {}
for line in sys.stdin:
    b, name, stat = line.rstrip("\n").split("|")
    ms, faults = stat.split()[:2]
    rows.setdefault(b, {}).setdefault(name, []).append((float(ms), float(faults)))
for b, by in rows.items():
    print(b)
    for name, r in by.items():
        ms = [x[0] for x in r]
        print(f"  {name:28} median {st.median(ms):6.2f} ms, least {min(ms):6.2f} ms, {st.median(x[1] for x in r):4.0f} page faults")
    whole = [x[0] for x in by["+ 500 steps (whole run)"]]
    loop = [x[0] for x in by["time loop (wall_seconds)"]]
    print(f"  whole process / time loop: {st.median(whole) / st.median(loop):.1f}x (medians), {min(whole) / min(loop):.1f}x (least)")
'
