"""Ctrl-C stops a run with KeyboardInterrupt (the GIL is released during the run, and the
run's monitor lets Python's signal handler speak every few steps)."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

import maglev_sim
from maglev_sim import Scenario


def interrupt_after(seconds: float) -> threading.Timer:
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_sigint_stops_a_long_run_with_keyboard_interrupt():
    # paper-5 at 10x its length: minutes of work, stopped after a quarter of a second.
    sc = Scenario.bundled("paper-5").set("t_end", 100.0)
    timer = interrupt_after(0.25)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        maglev_sim.run(sc)
    timer.join()
    assert time.monotonic() - start < 30.0


def test_other_threads_run_during_a_run():
    # The GIL is released: a Python thread counts while the run goes on.
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    thread = threading.Thread(target=count)
    thread.start()
    try:
        maglev_sim.run(Scenario.bundled("paper-4.2"))
    finally:
        stop.set()
        thread.join()
    assert len(ticks) > 10
