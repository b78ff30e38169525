"""Every CSV the project writes reads with a bare ``pandas.read_csv``: the header row gives
the columns (no comment line, no index column), every column holds numbers (float or int:
an empty cell is NaN) except the label columns, which hold words. The same files as
host-sim/cli/tests/csv_plain.rs, read by pandas itself. Skipped without pandas."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from conftest import ROOT, run_cli

pd = pytest.importorskip("pandas")

LABELS = {"receiver", "train", "point", "kind", "status", "error", "events"}


def header(text: str) -> list[str]:
    return next(csv.reader(text.splitlines()))


def check(what: str, text: str, path: Path) -> None:
    path.write_text(text)
    frame = pd.read_csv(path)
    names = header(text)
    assert list(frame.columns) == names, what
    assert len(frame) == len(text.splitlines()) - 1, what
    for name in names:
        kind = frame[name].dtype.kind
        if name in LABELS:
            assert kind in "OUT" or frame[name].isna().all(), (what, name, frame[name].dtype)
        else:
            assert kind in "fiu", (what, name, frame[name].dtype)


def cli_ok(args: list[str], cwd: Path) -> str:
    done = run_cli(args, cwd)
    assert done.returncode == 0, (args, done.stderr)
    return done.stdout


def test_every_csv_reads_with_bare_read_csv(tmp_path):
    n = iter(range(1000))
    scratch = lambda: tmp_path / f"read-{next(n)}.csv"  # noqa: E731
    files = []
    run = tmp_path / "run"
    cli_ok(["run", "paper-4.2", "--set", "t_end=0.02", "--out", str(run)], tmp_path)
    files += [run / "response.csv", run / "profile.csv"]
    ground = tmp_path / "ground"
    cli_ok(["run", "paper-5", "--set", "bridge.spans_m=[30.0, 30.0, 30.0]",
            "--set", "train=wheel-rail", "--set", "train.cars=1", "--set", "t_end=1.0",
            "--set", "dt=0.004", "--set", "ground.distances_m=[12.5, 25.0]",
            "--set", "ground.pier=2",
            "--set", 'output.probes=["pier2.base.az", "ground2.vz"]',
            "--out", str(ground)], tmp_path)
    files += [ground / "response.csv", ground / "ground.csv", ground / "ground-levels.csv"]
    hil = tmp_path / "hil"
    cli_ok(["hil", "paper-4.2", "--firmware", "inproc", "--set", "t_end=0.01",
            "--set", "fault=range:0@0.002", "--out", str(hil)], tmp_path)
    files += [hil / "response.csv", hil / "events.csv"]
    spec = tmp_path / "spec.toml"
    spec.write_text("scenario='moving-force'\n[set]\nt_end=0.02\ndt=0.001\n[axes]\n"
                    "speed=[10.0, -1.0]\n[reduce]\nquantities=['peak:midspan_z']\n")
    sweep = tmp_path / "sweep"
    cli_ok(["sweep", str(spec), "--out", str(sweep)], tmp_path)
    files += [sweep / "results.csv", sweep / "costs.csv"]
    for f in files:
        check(str(f.relative_to(tmp_path)), f.read_text(), scratch())
    history = tmp_path / "history.csv"
    history.write_text("t,a\n" + "".join(
        f"{j * 0.002!r},{((j % 10) - 4.5) * 0.1!r}\n" for j in range(5000)))
    trace = tmp_path / "trace.csv"
    trace.write_text("t,h\n0,0.01\n0.001,0.0099\n0.002,0.0098\n")
    bands = tmp_path / "bands.csv"
    cli_ok(["bands", "--input", str(history), "--column", "a", "--out", str(bands)], tmp_path)
    check("bands --out", bands.read_text(), scratch())
    for args in (
        ["bands", "--input", str(history), "--column", "a"],
        ["bands", "--input", str(history), "--column", "a", "--output", "velocity"],
        ["accelerogram", "--pga-g", "0.1", "--duration-s", "12"],
        ["irregularity", "--direction", "z", "--seed", "1", "--dx", "0.5", "--length", "20"],
        ["control", "--trace", str(trace), "--nsub", "10"],
        ["modes", "--format", "csv"],
    ):
        check(" ".join(args), cli_ok(args, tmp_path), scratch())
    # The report's CSVs, as `maglev report paper-5 --out docs/paper5` wrote them.
    for name in ("bands.csv", "ground-levels.csv", "ground-overall.csv"):
        f = ROOT / "docs" / "paper5" / name
        check(name, f.read_text(), scratch())
