"""`accelerogram` and `bands` against the CLI's commands: the same numbers."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import maglev_sim

from conftest import run_cli


def read_csv(path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return {
        name: np.array([float(r[j]) if r[j] != "" else math.nan for r in rows[1:]])
        for j, name in enumerate(rows[0])
    }


def test_accelerogram_is_the_commands_to_the_bit(tmp_path):
    args = ["accelerogram", "--pga-g", "0.2", "--ground", "soft", "--seed", "3",
            "--duration-s", "8", "--dt-s", "0.01", "--strong-end-s", "5"]
    done = run_cli(args, tmp_path)
    assert done.returncode == 0, done.stderr
    (tmp_path / "rec.csv").write_text(done.stdout)
    want = read_csv(tmp_path / "rec.csv")
    got = maglev_sim.accelerogram(pga_g=0.2, ground="soft", seed=3, duration_s=8.0, dt_s=0.01,
                                  strong_end_s=5.0)
    assert list(got) == list(want)
    for c in ("ax_m_per_s2", "ay_m_per_s2", "az_m_per_s2"):
        assert np.array_equal(got[c].view(np.uint64), want[c].view(np.uint64)), c
    # t is printed with Δt's decimals.
    assert np.max(np.abs(got["t_s"] - want["t_s"])) < 1e-12


def test_accelerogram_refuses_a_bad_value_naming_it():
    with pytest.raises(ValueError, match="pga_g"):
        maglev_sim.accelerogram(pga_g=5.0)
    with pytest.raises(ValueError, match="ground"):
        maglev_sim.accelerogram(pga_g=0.1, ground="rock")


def test_bands_are_the_commands_to_its_rounding(tmp_path):
    dt = 1e-3
    t = np.arange(4000) * dt
    a = 0.3 * np.sin(2 * np.pi * 12.5 * t) + 0.05 * np.sin(2 * np.pi * 80.0 * t + 0.4)
    with open(tmp_path / "h.csv", "w") as f:
        f.write("t,a\n")
        for ti, ai in zip(t, a):
            f.write(f"{float(ti)!r},{float(ai)!r}\n")
    for extra, kw in [([], {}), (["--output", "velocity", "--running", "1"],
                                 {"output": "velocity", "running": 1.0})]:
        out = tmp_path / "levels.csv"
        done = run_cli(["bands", "--input", str(tmp_path / "h.csv"), "--column", "a",
                        "--out", str(out)] + extra, tmp_path)
        assert done.returncode == 0, done.stderr
        want = read_csv(out)
        got = maglev_sim.bands(a, dt, **kw)
        level = [k for k in want if k != "centre_hz"][0]
        assert np.array_equal(got["centre_hz"], want["centre_hz"])
        # The CSV holds the level to 0.0001 dB: half of it is the rounding.
        assert np.nanmax(np.abs(got[level] - want[level])) <= 5e-5 + 1e-9, level
        assert np.array_equal(np.isnan(got[level]), np.isnan(want[level]))


def test_bands_refuse_bad_input_naming_it():
    with pytest.raises(ValueError, match="running"):
        maglev_sim.bands(np.zeros(100), 1e-3, running=-1.0)
    with pytest.raises(ValueError, match="quantity"):
        maglev_sim.bands(np.zeros(100), 1e-3, quantity="jerk")
