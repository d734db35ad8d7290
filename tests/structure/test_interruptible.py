"""Ctrl-C during a structure run is raised at once, not when the compiled run ends.

The engine's run is one compiled call; Python handles a signal only between
its own bytecodes, so a SIGINT or SIGTERM waited for the run's end (a
stiff damper's run for minutes, a large model's as long as it takes).  Each
run now goes on a thread of its own while the calling thread waits
(``frictionflow._interrupt.interruptible``).  The interpreter's exit waits for
a run an interrupt left behind (finalising under it crashed about one exit in
ten); the CLI ends at once instead.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from frictionflow.solvers.structure import simulate_system
import frictionflow.cli as cli
from frictionflow._interrupt import abandoned, interruptible
from frictionflow.system import System

from ..cli.processes import SRC, default_signals

N = 10
DOF = [f"x{i}" for i in range(N)]
CHAIN = {"dof": DOF, "mass": [1.0] * N,
         "spring": [{"on": {x: 1.0}, "k": 1.0} for x in DOF]
         + [{"on": {a: 1.0, b: -1.0}, "k": 0.5} for a, b in zip(DOF, DOF[1:])],
         "damper": [{"on": {x: 1.0}, "c": 0.04} for x in DOF],
         "contact": [{"on": {x: 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.2 if i % 2 == 0 else 0.1,
                      "fs": 0.4 if i % 2 == 0 else 0.35} for i, x in enumerate(DOF)],
         "initial": {"q": {x: 0.5 * float(np.sin(i + 1)) for i, x in enumerate(DOF)}}}

SCRIPT = f"""
import sys
from frictionflow._interrupt import abandoned
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import System
system = System.from_dict({CHAIN!r})
simulate_system(system, 1.0)  # the kernels compiled or loaded before the run that is interrupted
print("running", flush=True)
try:
    simulate_system(system, 2e4)  # about 55,000 switches: a second or more
except KeyboardInterrupt:
    print("interrupted while running" if abandoned() else "interrupted after the run", flush=True)
    sys.exit(3)  # the exit waits for the abandoned run: finalising under it crashed
print("finished", flush=True)
"""


def test_a_run_on_its_thread_gives_the_same_motion_and_raises_its_errors():
    system = System.from_dict(CHAIN)
    here = simulate_system(system, 30.0)
    assert len(here.switches) > 20 and here.energy_residual < 1e-12
    with pytest.raises(ZeroDivisionError):
        interruptible(lambda: 1 / 0)
    assert interruptible(lambda: 7) == 7


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_a_signal_during_a_long_run_interrupts_it_before_its_end():
    """The interrupt is raised while the run's thread is still at work (before, only once the run had ended)."""
    env = dict(os.environ, PYTHONPATH=str(SRC))
    p = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=env, preexec_fn=default_signals)
    assert p.stdout.readline().strip() == "running"
    time.sleep(0.3)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=300)
    assert out.strip() == "interrupted while running" and p.returncode == 3, err


def test_the_cli_ends_at_once_while_an_interrupted_run_is_at_work(monkeypatch):
    """``cli.run`` with a run's thread still alive leaves by ``os._exit`` with the command's code (the
    interpreter's exit would wait for the run); without one it ends as before."""
    release, started = threading.Event(), threading.Event()

    def at_work():
        started.set()
        interruptible(release.wait)

    left = threading.Thread(target=at_work, daemon=True)  # the call's own thread stays at work until released
    left.start()
    started.wait()
    exits = []

    def leave(code):
        exits.append(code)
        raise SystemExit(code)

    monkeypatch.setattr(cli, "main", lambda: 1)
    monkeypatch.setattr(cli.os, "_exit", leave)
    try:
        with pytest.raises(SystemExit):
            cli.run()
    finally:
        release.set()
        left.join()
    assert exits == [1]
    while abandoned():  # the released call returns
        time.sleep(0.01)
    with pytest.raises(SystemExit) as done:
        cli.run()
    assert done.value.code == 1 and exits == [1]
