"""The settings records of the continuations: how a branch is traced, as one value.

:func:`~frictionflow.orbits.continuation` takes a :class:`ContinuationSettings`,
:func:`~frictionflow.orbits.continue_forced` and
:func:`~frictionflow.orbits.forced_chart` a :class:`ForcedContinuationSettings`;
each also takes the record's fields as keywords (they replace the record's
values), so that ``continuation(model, law, "vb", 0.01, 0.3, n_equilibria=21)``
reads as it always did and a study can keep its settings in one value:

>>> from frictionflow.orbits.settings import ContinuationSettings
>>> coarse = ContinuationSettings(n_equilibria=21, max_points=100)
>>> coarse.step, coarse.max_points
(0.02, 100)
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any, Mapping, TypeVar

import numpy as np

from .. import _validate as check
from ..parameters import Param
from ..solvers.base import RK4_STEPS, Solver

#: where orbit branches of :func:`~frictionflow.orbits.continuation` can start
SEEDS = ("hopf", "start", "stop")
#: the points an orbit branch takes at most unless told: every continuation's, in the API and on the command line
MAX_POINTS = 400
#: the ranges of :class:`ContinuationSettings`' numbers (the command line's options check the same ranges)
CONTINUATION_RANGES = {p.name: p for p in (
    Param("transient", "", "seed and sweep simulations' length", "run", 500.0, lower=0.0, upper=1e9),
    Param("n_equilibria", "", "grid points of the equilibrium branch", "run", 101, kind="int", lower=2,
          upper=100_000),
    Param("max_points", "", "points per orbit branch", "run", MAX_POINTS, kind="int", lower=2, upper=100_000),
    Param("max_period", "", "period at which a branch ends", "run", 500.0, lower=0.0, lower_open=True, upper=1e6),
    Param("step", "", "first arclength step", "run", 0.02, lower=0.0, lower_open=True, upper=1.0),
    Param("max_step", "", "largest arclength step", "run", 0.1, lower=0.0, lower_open=True, upper=1.0),
    Param("returns", "", "crossings of the section per period", "run", 1, kind="int", lower=1, upper=64),
    Param("sweep", "", "brute-force simulations", "run", 0, kind="int", lower=0, upper=10_000),
    Param("tol", "", "Newton tolerance", "run", None, lower=0.0, lower_open=True, upper=1e-3),
)}
#: RK4 grid steps per forcing period unless told (doubled below Omega = 1/8, where they would be longer than
#: 2 pi / 64: ``solvers.base.rk4_steps``)
DEFAULT_STEPS = RK4_STEPS
#: the ranges of the forced orbits' integers (find_forced_orbit, continue_forced, stroboscopic_sweep and their
#: command-line options check these)
FORCED_RANGES = {p.name: p for p in (
    Param("m", "", "period in forcing periods", "run", 1, kind="int", lower=1, upper=1000),
    Param("steps", "", "RK4 steps per forcing period", "run", None, kind="int", lower=4, upper=1_000_000,
          default_text=f"{DEFAULT_STEPS}, doubled while a step exceeds 2 pi/64 (Omega < 1/8)"),
    Param("transient_periods", "", "forcing periods before shooting", "run", 200, kind="int", lower=0,
          upper=10_000_000),
)}

R = TypeVar("R")


@dataclass(frozen=True)
class ContinuationSettings:
    """How :func:`~frictionflow.orbits.continuation` seeds and traces its branches.

    Attributes
    ----------
    seeds:
        Where orbit branches start: ``hopf`` (every Hopf point in the
        interval), ``start``/``stop`` (the attractor a simulation of
        ``transient`` time units reaches at that end).
    transient:
        Length of the seed and sweep simulations.
    n_equilibria:
        Grid points of the equilibrium branch (Hopf points are added to it).
    max_points, max_period:
        A branch stops after this many points, or once its period exceeds
        ``max_period`` (reported as a ``period_blowup``).
    step, max_step:
        First and largest arclength step, in units of the interval length
        (and of max(F_s, |V_b|) along X).
    returns:
        Crossings of the section X' = 0 per period (2: period-2 orbits).
    sweep:
        Number of brute-force simulations across the interval (0: none).
    solver, x0, v0:
        Solver and start state of the seed and sweep simulations (defaults as
        :func:`frictionflow.simulate`); the solver also integrates each
        orbit's period for its power flow.
    tol:
        Newton tolerance on each orbit's X relative to max(F_s, |V_b|), as
        :func:`~frictionflow.orbits.find_orbit`'s (default: 1e-12 for
        piecewise-constant laws, 1e-9 otherwise).  It bounds the error in X,
        |G / (1 - mu)|, not the residual G: near a Hopf point (mu -> 1) every
        branch point is as accurate as a single orbit.
    progress:
        A progress bar on stderr per branch traced (its points, of at most ``max_points``).
    """

    seeds: tuple[str, ...] = SEEDS
    transient: float = 500.0
    n_equilibria: int = 101
    max_points: int = MAX_POINTS
    max_period: float = 500.0
    step: float = 0.02
    max_step: float = 0.1
    returns: int = 1
    sweep: int = 0
    solver: Solver | None = None
    x0: float | None = None
    v0: float | None = None
    tol: float | None = None
    progress: bool = False

    def __post_init__(self) -> None:
        for name, param in CONTINUATION_RANGES.items():  # one line naming the setting, before any work
            if getattr(self, name) is not None:
                param.check(getattr(self, name))
        check.instance("progress", self.progress, (bool, np.bool_), "True or False")


@dataclass(frozen=True)
class ForcedContinuationSettings:
    """How :func:`~frictionflow.orbits.continue_forced` traces a branch of forced orbits.

    Attributes
    ----------
    steps:
        RK4 grid steps per forcing period (None: 512, doubled while a step of the interval's
        slowest forcing would exceed 2 pi / 64: ``solvers.base.rk4_steps``).
    h0, h_max, h_min:
        First, largest and smallest step in scaled arclength (lambda over
        the interval's length, the state over the first orbit's size);
        0 < h_min <= h0 <= h_max.
    max_points:
        The branch stops after this many points.
    detect:
        Locate the special points (folds, period doublings, Neimark-Sacker,
        grazings) between accepted points.
    tol:
        Newton tolerance of each orbit.
    progress:
        A progress bar on stderr while the branch is traced (its points, of at most ``max_points``).
    """

    steps: int | None = None
    h0: float = 0.01
    h_max: float = 0.04
    h_min: float = 1e-6
    max_points: int = MAX_POINTS
    detect: bool = True
    tol: float = 1e-11
    progress: bool = False

    def __post_init__(self) -> None:
        check.instance("progress", self.progress, (bool, np.bool_), "True or False")


def merged(kind: type[R], given: R | None, options: Mapping[str, Any], where: str, name: str = "settings") -> R:
    """``given`` (default ``kind()``) with the keywords ``options`` replacing its fields.

    A keyword that is no field of ``kind`` is refused as Python refuses one
    (TypeError naming it, and the keywords ``where`` takes); ``given`` must
    be a ``kind`` (``name``: the argument it came as).
    """
    if given is not None and not isinstance(given, kind):
        raise TypeError(f"{where}(): {name} must be a {kind.__name__}, got {type(given).__name__}")
    allowed = [f.name for f in fields(kind)]  # type: ignore[arg-type]
    for key in options:
        if key not in allowed:
            raise TypeError(f"{where}() got an unexpected keyword argument {key!r}; "
                            f"the {kind.__name__} keywords are {', '.join(allowed)}")
    return replace(given if given is not None else kind(), **options)  # type: ignore[type-var]
