"""`run` against `maglev run`: the same columns to the bit, the same refusals."""

from __future__ import annotations

import numpy as np
import pytest

import maglev_sim
from maglev_sim import Scenario

from conftest import read_response, run_cli


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.mark.parametrize("name", ["paper-4.2", "paper-5"])
def test_columns_are_the_clis_to_the_bit(name, tmp_path):
    out = tmp_path / "out"
    done = run_cli(["run", name, "--out", str(out)], tmp_path)
    assert done.returncode == 0, done.stderr
    expected = read_response(out / "response.csv")
    got = maglev_sim.run(Scenario.bundled(name))
    assert list(got.columns) == list(expected)
    for column, want in expected.items():
        assert same_bits(got[column], want), column
    assert got.summary["steps"] == len(want) - 1


def test_probes_and_sets_are_the_clis(tmp_path):
    probes = ["wheel1.gap_z", "span1.midspan.z"]
    sc = Scenario.bundled("paper-4.2").set("speed", 100.0).set("t_end", 0.2)
    out = tmp_path / "out"
    args = ["run", "paper-4.2", "--set", "speed=100.0", "--set", "t_end=0.2",
            "--set", 'output.probes=["wheel1.gap_z","span1.midspan.z"]', "--out", str(out)]
    done = run_cli(args, tmp_path)
    assert done.returncode == 0, done.stderr
    expected = read_response(out / "response.csv")
    got = maglev_sim.run(sc, probes=probes)
    assert list(got.columns) == ["t", *probes, "iterations", "collision"]
    for column, want in expected.items():
        assert same_bits(got[column], want), column
    assert got.summary["case"]["speed_m_per_s"] == 100.0


@pytest.mark.parametrize(
    "key,value,names",
    [
        ("speed", -1.0, "run.speed_m_per_s"),
        ("nosuch", 1, "--set nosuch"),
        ("run.dt_s", 0, "run.dt_s"),
    ],
)
def test_a_bad_set_raises_value_error_with_the_clis_message(key, value, names, tmp_path):
    sc = Scenario.bundled("paper-4.2")
    with pytest.raises(ValueError) as e:
        sc.set(key, value)
    assert names in str(e.value)
    assert sc.sets == []  # left as it was
    done = run_cli(["run", "paper-4.2", "--set", f"{key}={value!r}", "--out", str(tmp_path / "o")], tmp_path)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines()[-1] == f"maglev: error: {e.value}"


def test_a_bad_probe_and_a_bad_name_raise_value_error():
    with pytest.raises(ValueError, match="output.probes"):
        maglev_sim.run("paper-4.2", probes=["wheel99.nothing"])
    with pytest.raises(ValueError, match="not a bundled name"):
        Scenario.bundled("paper-6")
    with pytest.raises(ValueError, match="scenario"):
        Scenario.from_toml("[run\n")


def test_from_toml_and_from_file_read_the_same_scenario(tmp_path):
    text = Scenario.bundled("paper-4.2").text
    path = tmp_path / "s.toml"
    path.write_text(text)
    a = maglev_sim.run(Scenario.from_toml(text).set("t_end", 0.05))
    b = maglev_sim.run(Scenario.from_file(str(path)).set("t_end", 0.05))
    for column in a.columns:
        assert same_bits(a[column], b[column]), column
    with pytest.raises(ValueError, match="nowhere.toml"):
        Scenario.from_file(str(tmp_path / "nowhere.toml"))


def test_case_is_a_dict_in_si():
    case = Scenario.bundled("paper-5").set("speed", 50.0).case()
    assert isinstance(case, dict)
    assert case["speed_m_per_s"] == 50.0
    assert case["dt_s"] > 0


def test_to_pandas_holds_the_columns():
    pd = pytest.importorskip("pandas")
    r = maglev_sim.run(Scenario.bundled("paper-4.2").set("t_end", 0.05))
    frame = r.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == list(r.columns)
    assert same_bits(frame["t"].to_numpy(), r["t"])


def test_stability_is_the_clis_report(tmp_path):
    done = run_cli(["stability", "--scenario", "unit", "--set", "speed=0.0", "--format", "json"], tmp_path)
    assert done.returncode == 0, done.stderr
    import json

    want = json.loads(done.stdout)
    got = maglev_sim.stability(Scenario.bundled("unit").set("speed", 0.0))
    assert got == want
    assert got["scenario"] == "unit"
    with pytest.raises(ValueError) as e:
        maglev_sim.stability(Scenario.bundled("moving-force"))
    refused = run_cli(["stability", "--scenario", "moving-force"], tmp_path)
    assert refused.returncode == 2
    assert refused.stderr.strip() == f"maglev: error: {e.value}"
