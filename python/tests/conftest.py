"""Shared helpers: the CLI binary the tests compare with, and its response.csv read back."""

from __future__ import annotations

import csv
import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def cli() -> list[str]:
    """The `maglev` binary: `$MAGLEV` if set, else the one cargo built (release first), else
    `cargo run --release`."""
    if os.environ.get("MAGLEV"):
        return [os.environ["MAGLEV"]]
    for profile in ("release", "debug"):
        exe = ROOT / "target" / profile / "maglev"
        if exe.is_file() and os.access(exe, os.X_OK):
            return [str(exe)]
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.skip("no maglev binary under target/ and no cargo to build one")
    return [cargo, "run", "--quiet", "--release", "-p", "maglev", "--manifest-path", str(ROOT / "Cargo.toml"), "--"]


def run_cli(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(cli() + args, cwd=cwd, capture_output=True, text=True)


def read_response(path: Path) -> dict[str, np.ndarray]:
    """response.csv by column: floats as written (an empty cell is NaN)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {
        name: np.array([float(r[j]) if r[j] != "" else math.nan for r in body])
        for j, name in enumerate(header)
    }
