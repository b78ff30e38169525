#!/usr/bin/env bash
# Compare the existing results of two `maglev` binaries (e.g. an older commit's and today's):
# the modes (4, 20, 80 elements), the control traces (every scalar and scheme on one gap
# trace), moving-force and paper-4.2 passages at 10/50/100/150 m/s, and validate's report and
# validation.json. Prints, per output, "bit-identical" or the largest difference relative to
# the column's peak. docs/regression.md has a measured run.
# Usage: scripts/compare-results.sh OLD_MAGLEV NEW_MAGLEV [OUT_DIR]
set -euo pipefail
old=$1 new=$2 out=${3:-target/compare-results}
rm -rf "$out"; mkdir -p "$out"
python3 - "$out" <<'PY'
import math, sys
# a gap trace: 10 mm nominal, a 1 mm step at 0.05 s, a 20 Hz ripple of 0.3 mm from 0.15 s
with open(f"{sys.argv[1]}/trace.csv", "w") as f:
    f.write("t,h\n")
    for i in range(3001):
        t = i * 1e-4
        h = 0.010 + (0.001 if t >= 0.05 else 0.0)
        h += 3e-4 * math.sin(2 * math.pi * 20 * t) if t >= 0.15 else 0.0
        f.write(f"{t!r},{h!r}\n")
PY
for side in old new; do
  bin=${!side}
  mkdir -p "$out/$side"
  for e in 4 20 80; do "$bin" modes --elements $e --count 12 --format csv >"$out/$side/modes-$e.csv"; done
  for s in f64 f32 i32f32 i4f28; do
    for sch in paper accurate; do
      "$bin" control --trace "$out/trace.csv" --scalar $s --scheme $sch >"$out/$side/control-$s-$sch.csv"
    done
  done
  for v in 10 50 100 150; do
    "$bin" run moving-force --set speed=$v --out "$out/$side/moving-force-$v" 2>/dev/null
    "$bin" run paper-4.2 --set speed=$v --out "$out/$side/paper-4.2-$v" 2>/dev/null
  done
  "$bin" validate --out "$out/$side/validate" >/dev/null 2>&1
done
python3 - "$out" <<'PY'
import csv, glob, json, os, struct, sys
out = sys.argv[1]
def same(a, b):
    """Two cells hold the same value: the same text, or numbers with the same f64 bits (the
    text may differ: `0` and `0.0`, `0.00001` and `1e-5`)."""
    if a == b:
        return True
    try:
        return struct.pack("<d", float(a)) == struct.pack("<d", float(b))
    except ValueError:
        return False
def table(path):
    rows = list(csv.reader(open(path)))
    return rows[0], rows[1:]
def compare(rel):
    ho, ro = table(f"{out}/old/{rel}")
    hn, rn = table(f"{out}/new/{rel}")
    if open(f"{out}/old/{rel}").read() == open(f"{out}/new/{rel}").read():
        return "bit-identical"
    if len(ro) != len(rn):
        return f"rows differ: {len(ro)} vs {len(rn)}"
    if ho == hn and all(len(r) == len(s) and all(map(same, r, s)) for r, s in zip(ro, rn)):
        return "bit-identical (every cell the same f64 or text; the text of numbers differs)"
    worst, notes = (0.0, ""), []
    for h in ho:
        if h not in hn:
            notes.append(f"column {h} gone")
            continue
        i, j = ho.index(h), hn.index(h)
        diff = [(k, r[i], s[j]) for k, (r, s) in enumerate(zip(ro, rn)) if not same(r[i], s[j])]
        if not diff:
            continue
        num = [(float(a), float(b)) for _, a, b in diff if a and b]
        if len(num) < len(diff):
            notes.append(f"{h}: {len(diff) - len(num)} empty cell(s) differ")
        peak = max((abs(float(r[i])) for r in ro if r[i]), default=0.0) or 1.0
        d = max((abs(a - b) for a, b in num), default=0.0) / peak
        if d == 1.0 or len(diff) <= 2:
            notes.append(f"{h}: {len(diff)} cell(s) differ, first at row {diff[0][0]} ({diff[0][1]} vs {diff[0][2]})")
        elif d > worst[0]:
            worst = (d, h)
    text = f"max rel. diff {worst[0]:.2e} ({worst[1]})" if worst[1] else "equal apart from"
    return text + ("; " + "; ".join(notes) if notes else "")
rels = sorted(os.path.relpath(p, f"{out}/old") for p in glob.glob(f"{out}/old/*.csv"))
rels += sorted(os.path.relpath(p, f"{out}/old") for p in glob.glob(f"{out}/old/*/response.csv"))
for rel in rels:
    if rel != "trace.csv":
        print(f"{rel}: {compare(rel)}")
ro = open(f"{out}/old/validate/report.md").read().splitlines()
rn = open(f"{out}/new/validate/report.md").read().splitlines()
changed = [k for k, (a, b) in enumerate(zip(ro, rn)) if a != b and "s wall" not in a]
print(f"validate/report.md: {len(ro)} vs {len(rn)} lines; lines that differ other than wall time: {changed or 'none'}")
def leaves(x, p=""):
    if isinstance(x, dict):
        for k, v in x.items(): yield from leaves(v, f"{p}.{k}")
    elif isinstance(x, list):
        for k, v in enumerate(x): yield from leaves(v, f"{p}[{k}]")
    else:
        yield p, x
jo = dict(leaves(json.load(open(f"{out}/old/validate/validation.json"))))
jn = dict(leaves(json.load(open(f"{out}/new/validate/validation.json"))))
worst = max(((abs(v - jn[k]) / abs(v), k) for k, v in jo.items()
             if k in jn and "wall" not in k and isinstance(v, float) and v != 0), default=(0, ""))
print(f"validate/validation.json: keys {len(jo)} vs {len(jn)}; largest relative change of a number "
      f"(wall times aside) {worst[0]:.2e} at {worst[1]}")
PY
