"""A worked study (docs/python.md): the §4.2 span's midspan deflection and the magnet's gap
over a sweep of speeds, into a pandas frame and a plot.

    python python/examples/speed_sweep.py [OUT_DIR]

writes OUT_DIR/python-speed-sweep.csv (the frame) and OUT_DIR/python-speed-sweep.svg (the
plot; needs matplotlib), OUT_DIR defaulting to docs/. Needs pandas.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd

import maglev_sim

SPEEDS_M_PER_S = [25.0, 50.0, 75.0, 100.0, 125.0, 150.0]
PROBES = ["span1.midspan.z", "wheel1.gap_z"]


def study() -> pd.DataFrame:
    rows = []
    for v in SPEEDS_M_PER_S:
        scenario = maglev_sim.Scenario.bundled("paper-4.2").set("speed", v)
        # The time to cross the 25 m span and leave it by one span more.
        scenario.set("t_end", 50.0 / v)
        run = maglev_sim.run(scenario, probes=PROBES)
        frame = run.to_pandas()
        h0 = run.summary["case"]["controller"]["h0_m"]
        rows.append(
            {
                "speed_m_per_s": v,
                "max_midspan_deflection_mm": -1e3 * frame["span1.midspan.z"].min(),
                "max_gap_deviation_mm": 1e3 * np.max(np.abs(frame["wheel1.gap_z"] - h0)),
                "mean_iterations": run.summary["mean_iterations"],
            }
        )
    return pd.DataFrame(rows)


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "docs"
    out.mkdir(parents=True, exist_ok=True)
    frame = study()
    frame.to_csv(out / "python-speed-sweep.csv", index=False, float_format="%.6g")
    print(frame.to_string(index=False))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot", file=sys.stderr)
        return
    matplotlib.rcParams["svg.hashsalt"] = "maglev"  # the same SVG from the same frame
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(frame["speed_m_per_s"], frame["max_midspan_deflection_mm"], "o-", label="midspan deflection")
    ax.plot(frame["speed_m_per_s"], frame["max_gap_deviation_mm"], "s-", label="|gap − h0| of wheel 1")
    ax.set_xlabel("speed (m/s)")
    ax.set_ylabel("peak (mm)")
    ax.set_title("paper-4.2: peaks over speed")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "python-speed-sweep.svg", metadata={"Date": None})
    print(f"wrote {out / 'python-speed-sweep.csv'} and {out / 'python-speed-sweep.svg'}")


if __name__ == "__main__":
    main()
