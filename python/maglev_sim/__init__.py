"""The maglev simulator from Python.

A :class:`Scenario` is what ``maglev run SCENARIO --set key=value ...`` takes: a bundled
scenario, a TOML text or a file, with the same overrides and the same errors.
:func:`run` runs it (the GIL released, Ctrl-C raising ``KeyboardInterrupt``) and returns a
:class:`Run`: response.csv's columns as numpy arrays and the summary as a dict. A controller
written in Python (an object with the ``start``/``forces``/``commit`` methods of the
simulator's ``Magnets``) can drive the run in place of the core's laws. docs/python.md is
the guide.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np

from ._native import BUNDLED, Scenario, _RustPd, accelerogram, bands, stability
from ._native import run as _run

__all__ = ["BUNDLED", "Scenario", "Run", "accelerogram", "bands", "run", "stability"]


class Run:
    """One finished run: ``columns`` (response.csv's, in its order: ``t``, the probes,
    ``iterations``, ``collision``; SI, NaN where a probe does not apply) and ``summary``
    (summary.json's counters: ``steps``, ``simulated_seconds``, ``wall_seconds``,
    ``mean_iterations``, ``unconverged_steps``, ``collision_steps``, ``gaps``, ``case``...).
    """

    __slots__ = ("columns", "summary")

    def __init__(self, columns: Mapping[str, np.ndarray], summary: dict[str, Any]):
        self.columns: dict[str, np.ndarray] = dict(columns)
        self.summary: dict[str, Any] = summary

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def __repr__(self) -> str:
        return f"Run({self.summary['scenario']!r}, {len(self.columns)} columns, {self.summary['steps']} steps)"

    def to_pandas(self):
        """The columns as a pandas DataFrame (pandas is optional: ``pip install pandas``)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Run.to_pandas needs pandas: pip install pandas") from e
        return pd.DataFrame(self.columns)


def run(
    scenario: Scenario | str,
    probes: Sequence[str] | None = None,
    controller: Any = None,
) -> Run:
    """Runs ``scenario`` (a :class:`Scenario`, or a bundled name) as ``maglev run`` does.

    ``probes`` replaces the scenario's ``output.probes`` (the same names, docs/scenarios.md);
    ``controller`` is a Python object with the ``Magnets`` methods (docs/python.md) that
    drives every magnet instead of the core's laws. Raises ``ValueError`` with the CLI's
    message on bad input and ``KeyboardInterrupt`` when interrupted. A run with steps that
    did not converge returns, as the CLI writes its outputs: check
    ``summary["unconverged_steps"]``.
    """
    if isinstance(scenario, str):
        scenario = Scenario.bundled(scenario)
    columns, summary = _run(scenario, list(probes) if probes is not None else None, controller)
    return Run(columns, summary)
