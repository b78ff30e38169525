"""A controller written in Python drives a run step-lockstep, and agrees with the same law
written in Rust (maglev_sim._RustPd)."""

from __future__ import annotations

import numpy as np
import pytest

import maglev_sim
from maglev_sim import Scenario, _RustPd

# Gains for the unit (a 600 kg magnet under a 3.75 t body): the magnet's mode near 9 Hz,
# damped; a slow integral that takes the bridge's sag out.
KP, KD, KI, KY, CY = 2.0e6, 2.0e4, 4.0e6, 1.0e6, 1.0e4


class PythonPd:
    """The law of `_RustPd`, in Python: G_z = p0 + kp·e + kd·ė + ki·∫e, G_y = −(ky·d + cy·ḋ)."""

    def __init__(self, kp, kd, ki=0.0, ky=0.0, cy=0.0):
        self.kp, self.kd, self.ki, self.ky, self.cy = kp, kd, ki, ky, cy
        self.calls = 0
        self.commits = 0

    def start(self, info):
        self.h0, self.dt = info["h0_m"], info["dt_s"]
        self.p0 = np.array(info["p0_N"])
        self.integral = np.zeros(info["wheels"])
        self.trial = self.integral.copy()
        assert info["gaps_m"].shape == (info["wheels"], 2)

    def forces(self, step, t, gaps_prev, gaps_next, accels):
        self.calls += 1
        out = np.empty((len(self.p0), 2))
        for w in range(len(self.p0)):
            hp, dp = gaps_prev[w]
            h, d = gaps_next[w]
            e = h - self.h0
            self.trial[w] = self.integral[w] + e * self.dt
            out[w, 0] = self.p0[w] + self.kp * e + self.kd * (h - hp) / self.dt + self.ki * self.trial[w]
            out[w, 1] = -(self.ky * d + self.cy * (d - dp) / self.dt)
        return out

    def commit(self, step, t):
        self.commits += 1
        self.integral = self.trial.copy()


def unit():
    return Scenario.bundled("unit").set("t_end", 0.5)


PROBES = ["wheel1.gap_z", "wheel1.force_z", "car1.body.z", "span1.midspan.z"]


def test_a_python_pd_law_matches_the_same_law_in_rust():
    py = PythonPd(KP, KD, KI, KY, CY)
    a = maglev_sim.run(unit(), probes=PROBES, controller=py)
    b = maglev_sim.run(unit(), probes=PROBES, controller=_RustPd(KP, KD, KI, KY, CY))
    steps = a.summary["steps"]
    assert steps == 500 and py.commits == steps and py.calls >= steps
    for name in PROBES:
        scale = np.max(np.abs(b[name]))
        assert scale > 0, name
        np.testing.assert_allclose(a[name], b[name], rtol=0, atol=1e-12 * scale, err_msg=name)
    # The law held the magnet: the gap moved (the bridge sags under the unit), within 5 % of h0.
    gap = a["wheel1.gap_z"]
    h0 = a.summary["case"]["controller"]["h0_m"]
    assert np.ptp(gap) > 1e-5
    assert np.max(np.abs(gap - h0)) < 0.05 * h0
    assert a.summary["collision_steps"] == 0


def test_the_python_law_is_the_one_that_drives():
    # Twice the stiffness moves the magnet less: the run reads the Python law's forces.
    soft = maglev_sim.run(unit(), probes=PROBES, controller=PythonPd(KP, KD))
    stiff = maglev_sim.run(unit(), probes=PROBES, controller=PythonPd(2 * KP, KD))
    h0 = soft.summary["case"]["controller"]["h0_m"]
    assert np.max(np.abs(stiff["wheel1.gap_z"] - h0)) < 0.8 * np.max(np.abs(soft["wheel1.gap_z"] - h0))


def test_an_exception_in_the_controller_ends_the_run_with_it():
    class Broken(PythonPd):
        def forces(self, step, t, *args):
            if step == 3:
                raise ZeroDivisionError("step 3")
            return super().forces(step, t, *args)

    with pytest.raises(ZeroDivisionError, match="step 3"):
        maglev_sim.run(unit(), controller=Broken(KP, KD))


def test_a_wrong_shape_of_forces_is_a_value_error():
    class Short(PythonPd):
        def forces(self, *args):
            return np.zeros((0, 2))

    with pytest.raises(ValueError, match="controller.forces"):
        maglev_sim.run(unit(), controller=Short(KP, KD))
