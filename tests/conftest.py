"""Shared fixtures and closed forms derived for the tests (not taken from the code under test)."""

from __future__ import annotations

import math
import signal
import subprocess

import numpy as np
import pytest

from frictionflow import BeltOscillator, Karnopp, RK4, simulate
from frictionflow import _compile_ahead

from . import scheduling


def slip_solution(t, x0, v0, force, zeta):
    """Closed form of X'' + 2 zeta X' + X = force (underdamped, zeta < 1)."""
    w = math.sqrt(1.0 - zeta * zeta)
    y0 = x0 - force
    b = (v0 + zeta * y0) / w
    e = np.exp(-zeta * t)
    c, s = np.cos(w * t), np.sin(w * t)
    x = force + e * (y0 * c + b * s)
    v = e * ((-zeta * y0 + w * b) * c + (-zeta * b - w * y0) * s)
    return x, v


def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile`` with the workers taking the files from two ends (:mod:`tests.scheduling`)."""
    if config.getvalue("dist") == "loadfile" and scheduling.usable():
        return scheduling.TwoEnded(config, log)
    return None


@pytest.fixture(scope="session")
def case1_run():
    """Paper Case I (zeta = 0, F_d = 0.02, V_b = 0.01), RK4 dt = 1e-3, 200 time units."""
    return simulate(BeltOscillator(zeta=0.0, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3), t_end=200.0)


@pytest.fixture(scope="session", autouse=True)
def no_compile_ahead():
    """No test starts a second compiling process by the way (a first CLI run on an empty cache would): the workers
    have the cores.  The tests of that process use :func:`spawned`."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(_compile_ahead.ENV, "0")
        yield


@pytest.fixture(autouse=True)
def signals_restored():
    """Each test leaves SIGINT's and SIGTERM's handlers as it found them.  ``frictionflow.cli.run`` ignores both once
    its command has ended, and a test that called it in-process left its worker ignoring SIGTERM: every later
    child of that worker inherited it, and a test signalling a child waited 120 s for an exit that never came."""
    handlers = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    yield
    for sig, handler in handlers.items():
        if handler is not None:
            signal.signal(sig, handler)


class Spawned:
    """The second processes :func:`frictionflow._compile_ahead.compile_ahead` started: their argv and the children
    (running ``command`` instead when set); ``forbid()`` makes any start fail the test."""

    def __init__(self) -> None:
        self.argv: list[list[str]] = []
        self.children: list[subprocess.Popen] = []
        self.command: list[str] | None = None
        self.forbidden = False

    def forbid(self) -> None:
        self.forbidden = True


@pytest.fixture
def spawned(monkeypatch):
    """A :class:`Spawned` log of the processes compiled ahead, with compiling ahead turned on and two usable cores
    (``subprocess.Popen`` and ``usable_cores`` replaced where ``compile_ahead`` reads them)."""
    log, real = Spawned(), subprocess.Popen

    def popen(argv, **kwargs):
        assert not log.forbidden, f"started {argv}"
        log.argv.append(argv)
        log.children.append(real(log.command or argv, **kwargs))
        return log.children[-1]

    monkeypatch.delenv(_compile_ahead.ENV)
    monkeypatch.setattr(_compile_ahead.subprocess, "Popen", popen)
    monkeypatch.setattr(_compile_ahead, "usable_cores", lambda: 2)
    return log
