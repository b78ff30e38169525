"""Python-side overhead of `maglev_sim.run` against the CLI's time loop (a benchmark, not a
test; docs/python.md "Overhead").

    python python/bench/overhead.py [SCENARIO] [REPEATS]

For each repeat, `maglev run SCENARIO` (the binary cargo built, as the tests find it) and
`maglev_sim.run(SCENARIO)`, interleaved; it prints the medians of the CLI's time loop
(summary.json `wall_seconds`), the Python call (everything from the call to the returned
arrays), and the overhead of the call against the CLI's loop. The target is 5 %.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from conftest import cli  # noqa: E402

import maglev_sim  # noqa: E402


def main() -> None:
    name = sys.argv[1] if len(sys.argv) > 1 else "paper-5"
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    loop_cli, call_py, loop_py = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeats):
            out = Path(tmp) / f"o{k}"
            subprocess.run(cli() + ["run", name, "--out", str(out)], check=True, capture_output=True)
            loop_cli.append(json.loads((out / "summary.json").read_text())["wall_seconds"])
            scenario = maglev_sim.Scenario.bundled(name)
            start = time.perf_counter()
            r = maglev_sim.run(scenario)
            call_py.append(time.perf_counter() - start)
            loop_py.append(r.summary["wall_seconds"])
    cli_s, py_s, py_loop = (statistics.median(x) for x in (loop_cli, call_py, loop_py))
    print(f"{name}, {repeats} repeats (medians)")
    print(f"  CLI time loop        {cli_s:8.3f} s")
    print(f"  Python run() call    {py_s:8.3f} s   ({100 * (py_s / cli_s - 1):+.1f} % of the CLI's loop)")
    print(f"  its own time loop    {py_loop:8.3f} s   (call - loop: {100 * (py_s / py_loop - 1):+.2f} %)")


if __name__ == "__main__":
    main()
