"""Type stubs of the extension module (python/src/)."""

from typing import Any, Sequence

import numpy as np

BUNDLED: list[str]
"""The names `Scenario.bundled` knows."""

class Scenario:
    """A scenario and its `--set` overrides, as `maglev run SCENARIO --set key=value` takes
    them; every check is the CLI's."""

    @property
    def name(self) -> str:
        """The name errors give: the bundled name, the path, or `from_toml`'s `name`."""
    @property
    def sets(self) -> list[str]:
        """The overrides so far, `key=value`."""
    @property
    def text(self) -> str:
        """The TOML text, before the overrides."""
    @staticmethod
    def bundled(name: str) -> Scenario:
        """A bundled scenario (`BUNDLED`); `ValueError` for another name."""
    @staticmethod
    def from_toml(text: str, name: str = "<text>") -> Scenario:
        """A scenario from its TOML text; `ValueError` with the CLI's message if it is not one."""
    @staticmethod
    def from_file(path: str) -> Scenario:
        """A scenario from a TOML file."""
    def set(self, key: str, value: bool | int | float | str) -> Scenario:
        """Overrides `key` as `--set key=value` does (short keys such as `speed`, `dt`,
        `t_end`, or `section.key`); `ValueError` naming the key on a bad one, the scenario
        left as it was. Returns the scenario."""
    def case(self) -> dict[str, Any]:
        """The case a run uses: every value in SI, the unit in each key (summary.json's `case`)."""

def run(
    scenario: Scenario, probes: Sequence[str] | None = None, controller: Any = None
) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """One run: response.csv's columns as arrays, and the summary (`maglev_sim.run` wraps it)."""

def stability(scenario: Scenario, girder_modes: int = 8) -> dict[str, Any]:
    """`maglev stability --scenario`'s report (poles, margins, critical magnet mass), a dict."""

def accelerogram(
    pga_g: float,
    ground: str = "medium",
    vertical_ratio: float = 2.0 / 3.0,
    duration_s: float = 20.0,
    dt_s: float = 0.005,
    seed: int = 0,
    rise_s: float = 2.0,
    strong_end_s: float = 10.0,
    decay_per_s: float = 0.4,
) -> dict[str, np.ndarray]:
    """`maglev accelerogram`'s record: `t_s`, `ax_m_per_s2`, `ay_m_per_s2`, `az_m_per_s2`
    (the same bits); `ValueError` naming the keyword outside its limits."""

def bands(
    values: np.ndarray,
    dt_s: float,
    quantity: str = "acceleration",
    output: str = "acceleration",
    running: float | None = None,
) -> dict[str, Any]:
    """`maglev bands`'s one-third-octave levels of `values` (every `dt_s` s): `centre_hz`, the
    command's level column (dB, NaN for a band without energy, unrounded), `rms`, `method`."""

class _RustPd:
    """A PD law with an integral term, in Rust: the tests' reference for a Python controller."""

    def __init__(
        self, kp: float, kd: float, ki: float = 0.0, ky: float = 0.0, cy: float = 0.0
    ) -> None: ...
