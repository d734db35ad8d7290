"""Compile the analysis kernels in a second process while a first run compiles its solver.

On an empty numba cache, a first ``frictionflow simulate`` compiles the
solver's kernels, runs, then compiles the analysis kernels: each about half
of its time.  numba keeps compiled kernels in files, so a second process can
compile the analysis kernels on another core meanwhile, and the run then
loads them from the cache.  Nothing happens when they are cached already or
on a single core; if the second process fails, the run compiles them itself.
"""

from __future__ import annotations

import subprocess
from typing import Callable

import numpy as np

from .._compile_ahead import compile_ahead, is_cached
from ..core import certificate, sections
from ..core.layout import N_WORK
from ..friction import Coulomb
from ..params import BeltOscillator
from ..trajectory import Trajectory
from . import analyze

#: how long a run waits for the second process before compiling itself
TIMEOUT = 300.0


def _cached() -> bool:
    """The classifier is cached (what the others are compiled with)."""
    return is_cached(sections.classify)


def in_background() -> Callable[[], None]:
    """Start compiling the analysis kernels in a child process unless they are cached; returns ``wait()``.

    Call ``wait()`` before analysing: the kernels are then loaded from the cache.
    """
    child = compile_ahead(__name__, _cached())
    if child is None:
        return lambda: None

    def wait() -> None:
        try:
            child.wait(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            child.kill()

    return wait


def compile_analysis() -> None:
    """Analyse a made-up periodic trajectory: compiles what analysing a real one needs, with the same types."""
    t = np.linspace(0.0, 60.0, 601)
    x, v = 0.02 * np.cos(t), -0.02 * np.sin(t)
    mode = np.where(v < 0.01, 1, 0).astype(np.int8)
    dwork = np.zeros((len(t), N_WORK))
    law = Coulomb(0.02, 0.04)
    traj = Trajectory.single_mass(t, x, v, x.copy(), mode, dwork, model=BeltOscillator(0.05, 0.01), friction=law,
                                  solver={"name": "exact"})
    analyze(traj)
    certificate.radius(law, 0.05, 0.01)  # (a run that ends sliding with the belt asks for it)


if __name__ == "__main__":
    compile_analysis()
