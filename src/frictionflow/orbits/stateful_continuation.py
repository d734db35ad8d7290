"""Continuation in one parameter for laws with internal state: steady sliding, its Hopf points, cycle branches.

What :func:`~.continuation.continuation` runs for a
:class:`~frictionflow.friction.stateful.StatefulLaw`: steady sliding on a grid
with its eigenvalues on the whole state (:mod:`.stateful_equilibria`), a branch
of cycles from every Hopf point and from the attractors long runs reach at the
interval's ends (:mod:`.stateful_cycles`), each point with its power flow over
one period of the stiff solver.
"""

from __future__ import annotations

import math

import numpy as np

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..solvers.stiff import Stiff
from .branches import Bifurcation, Branch, BranchPoint, ContinuationResult
from .errors import ShootingError
from .flow_stiff import check_stateful
from .measures import equilibrium_measures, measures_of
from .parameters import with_param
from .settings import SEEDS, ContinuationSettings
from .stateful import find_stateful_orbit, stick_fraction
from .stateful_cycles import CycleSolution, StateCycleProblem, branch_from_hopf, branch_from_orbit
from .stateful_equilibria import state_equilibrium_branch, state_hopf_points
from .tracing import StepControl, Trace

#: the first cycle of a branch born at a Hopf point: this fraction of the state's scale from steady sliding
HOPF_AMPLITUDE = 4e-3


def check_settings(model: BeltOscillator, law: FrictionLaw, param: str, ends: tuple[float, float],
                   s: ContinuationSettings) -> None:
    """Refuse, before any work, what this continuation cannot run; ValueError naming it."""
    for name, v in zip(("from", "to"), ends, strict=True):
        if not math.isfinite(v):
            raise ValueError(f"{name} must be a finite number, got {v!r}")
    if ends[0] == ends[1]:
        raise ValueError(f"from and to must differ, got {ends[0]!r} twice")
    if s.tol is not None and not (isinstance(s.tol, (int, float)) and 0.0 < s.tol <= 1e-3):
        raise ValueError(f"tol must be a number in (0, 1e-3], got {s.tol!r}")
    if s.returns != 1 or s.sweep:
        raise ValueError(f"returns must be 1 and sweep 0 for friction={law.name} (period-k cycles and overlays "
                         "of laws with internal state are not run yet)")
    if model.forced:
        raise ValueError(f"fex must be 0 here: continue the unforced oscillator with friction={law.name}")
    for seed in s.seeds:
        if seed not in SEEDS:
            raise ValueError(f"seeds must be among {', '.join(SEEDS)}, got {seed!r}")
    for v in ends:
        check_stateful(*with_param(model, law, param, v))


def stateful_continuation(model: BeltOscillator, law: FrictionLaw, param: str, start: float, stop: float,
                          s: ContinuationSettings) -> ContinuationResult:
    """Steady sliding, its Hopf points and the cycle branches of (model, law) in ``param`` (module docstring)."""
    check_settings(model, law, param, (start, stop), s)
    grid = np.linspace(start, stop, max(2, s.n_equilibria))
    hopfs = state_hopf_points(model, law, param, grid)
    values = np.array(sorted(set(grid.tolist()) | set(hopfs), reverse=stop < start))
    eqs = state_equilibrium_branch(model, law, param, values)
    branches = [Branch("equilibrium", [_equilibrium_point(model, law, param, eq) for eq in eqs],
                       seed="sliding equilibrium", end="interval end")] if eqs else []
    bifs = [Bifurcation("hopf", lam, 0, {}) for lam in hopfs]
    problem = StateCycleProblem(model, law, param, start, stop, tol=s.tol, max_period=s.max_period)
    steps = StepControl(h0=s.step, h_max=s.max_step, max_points=s.max_points)
    if "hopf" in s.seeds:
        for lam in hopfs:
            try:
                trace = branch_from_hopf(problem, lam, HOPF_AMPLITUDE * problem.sx, steps)
            except (RuntimeError, ValueError):
                continue
            _add(branches, bifs, problem, trace, f"hopf at {param}={lam:.10g}")
    for which, lam, toward in (("start", start, stop), ("stop", stop, start)):
        if which in s.seeds:
            _from_end(branches, bifs, problem, (lam, toward), s, steps)
    bifs.sort(key=lambda b: (b.value - start) / (stop - start))
    return ContinuationResult(param=param, start=float(start), stop=float(stop),
                              params={**model.report(), **law.as_dict()}, branches=branches, bifurcations=bifs)


def _from_end(branches: list[Branch], bifs: list[Bifurcation], problem: StateCycleProblem, ends: tuple[float, float],
              s: ContinuationSettings, steps: StepControl) -> None:
    """The branch through the attractor a run at lambda = ends[0] reaches, traced toward ends[1] (if new)."""
    lam, toward = ends
    model, law = with_param(problem.model, problem.law, problem.param, lam)
    try:
        orbit = find_stateful_orbit(model, law, x0=s.x0, v0=s.v0, transient=s.transient, solver=s.solver)
    except ShootingError:
        return  # the run settled on steady sliding
    if any(b.kind == "periodic" and any(abs(p.value - lam) <= 1e-9 * problem.sl and abs(p.x - orbit.state[0])
                                        <= 1e-6 * problem.sx for p in b.points) for b in branches):
        return  # on a branch already traced
    try:
        trace = branch_from_orbit(problem, lam, orbit.state, orbit.period, toward, steps)
    except (RuntimeError, ValueError):
        return
    _add(branches, bifs, problem, trace, f"simulation at {problem.param}={lam:.10g}")


def _equilibrium_point(model: BeltOscillator, law: FrictionLaw, param: str, eq) -> BranchPoint:  # noqa: ANN001
    m, lw = with_param(model, law, param, eq.value)
    return BranchPoint(value=eq.value, kind="equilibrium", stability=eq.stability, x=eq.x,
                       measures=equilibrium_measures(eq.x, m.vb, lw.fd),
                       eigenvalues=tuple(complex(e) for e in eq.eigenvalues))


def _cycle_point(problem: StateCycleProblem, s: CycleSolution) -> BranchPoint:
    """A branch point with its power flow over one period of the stiff solver from the cycle's state."""
    model, law = with_param(problem.model, problem.law, problem.param, s.lam)
    traj = Stiff(rtol=1e-10, atol=1e-12).solve_state(model, law, s.y0, s.period)
    mu = s.multipliers[0]
    stability = "stable" if abs(mu) < 1.0 - 1e-7 else ("unstable" if abs(mu) > 1.0 + 1e-7 else "neutral")
    return BranchPoint(value=s.lam, kind="periodic", stability=stability, x=float(s.y0[0]), measures=measures_of(traj),
                       period=s.period, multiplier=complex(mu), stick_fraction=stick_fraction(traj))


def _add(branches: list[Branch], bifs: list[Bifurcation], problem: StateCycleProblem, trace: Trace, seed: str) -> None:
    index = len(branches)
    branches.append(Branch("periodic", [_cycle_point(problem, s) for s in trace.solutions], seed=seed, end=trace.end))
    bifs.extend(Bifurcation(e.type, e.value, index, e.detail) for e in trace.events)
