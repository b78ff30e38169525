#!/usr/bin/env bash
# The sharp peaks of a resonance sweep's results.csv (host-sim/cli/sweeps/resonance.toml,
# docs/resonance.md): local maxima of |COLUMN| that are the largest within ±0.1 s of passing
# period T = 25/v, as host-sim/sim/tests/resonance_speed.rs finds them.
# Usage: bash host-sim/cli/sweeps/resonance-peaks.sh DIR/results.csv [COLUMN, default max:midspan_z]
set -euo pipefail
col=${2:-max:midspan_z}
awk -F, -v col="$col" '
NR == 1 { for (i = 1; i <= NF; i++) if ($i == col) c = i; if (!c) { print "no column " col > "/dev/stderr"; exit 2 } next }
{ n++; v[n] = $1; a[n] = ($c < 0 ? -$c : $c); t[n] = 25.0 / $1 }
END {
  print "speed_m_per_s,T_s," col
  for (i = 2; i < n; i++) {
    if (!(a[i] > a[i-1] && a[i] > a[i+1])) continue
    best = 1
    for (j = 1; j <= n; j++) if (j != i && (t[j] - t[i] < 0 ? t[i] - t[j] : t[j] - t[i]) <= 0.1 && a[j] >= a[i]) best = 0
    if (best) printf "%s,%.3f,%.4e\n", v[i], t[i], a[i]
  }
}' "$1"
