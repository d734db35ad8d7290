"""Continuation in one parameter: equilibria, their Hopf points, and branches of periodic orbits.

:func:`continuation` puts the pieces together:

1. the sliding equilibrium on a grid of the interval, with its Hopf points
   (sign changes of 2 zeta + F'(V_b), refined);
2. a branch of orbits from every Hopf point (subcritical or supercritical:
   whichever side the cycles appear on);
3. branches through the attractors long simulations reach at the interval's
   ends (stick-slip cycles are never born at a Hopf point);
4. optionally, a brute-force sweep of simulations to overlay.

A seed that lies on a branch already traced is skipped.  Every point carries
its power flow (P_fin, P_df, P_dv, R_c, R_f, P_belt, P_heat) and TR_B.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _validate as check
from ..estimate import Estimate, enforce
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..solvers.base import Solver
from ..solvers.registry import auto_solver
from .branches import Bifurcation, Branch, BranchPoint, ContinuationResult
from .cycle_problem import CycleProblem, Solution
from .equilibria import equilibrium, equilibrium_branch, hopf_points
from .flow import flow_cost, make_flow
from .parameters import MODEL_PARAMS, with_param
from .shooting import Shooting, ShootingError, find_orbit, orbit_from_segment, shooting_estimate
from .stateful_continuation import stateful_continuation
from .brute_force import sweep as brute_force_sweep
from .hybrid import MAX_TIME
from .settings import SEEDS, ContinuationSettings, merged
from .tracing import StepControl, Trace, Tracer


def continuation(
    model: BeltOscillator,
    friction: FrictionLaw,
    param: str,
    start: float,
    stop: float,
    *,
    settings: ContinuationSettings | None = None,
    **options: Any,
) -> ContinuationResult:
    """Continue equilibria and periodic orbits in ``param`` from ``start`` to ``stop``.

    Parameters
    ----------
    model, friction:
        The oscillator and its friction law at the other parameters' values.
    param:
        zeta, vb, or a parameter of the friction law (fd, fs, vd, vs, delta, viscous).

    start, stop:
        The interval's ends (finite, distinct; either order).
    settings:
        How branches are seeded and traced (:class:`~.settings.ContinuationSettings`;
        default: its defaults).
    **options:
        Fields of :class:`~.settings.ContinuationSettings` (described there),
        replacing those of ``settings``; a TypeError names any other keyword.
        ``seeds``: where orbit branches start, ``hopf`` (every Hopf point in
        the interval), ``start``/``stop`` (the attractor a simulation reaches
        at that end) [all three]; ``transient``: length of the seed and sweep
        simulations [500]; ``n_equilibria``: grid points of the equilibrium
        branch [101]; ``max_points``, ``max_period``: a branch ends after this
        many points [400] or once its period exceeds this [500]; ``step``,
        ``max_step``: first and largest arclength step, relative to the
        interval [0.02, 0.1]; ``returns``: section crossings per period [1];
        ``sweep``: brute-force simulations across the interval [0: none];
        ``solver``, ``x0``, ``v0``: of the seed and sweep simulations (and of
        each orbit's power flow) [as :func:`frictionflow.simulate`]; ``tol``:
        Newton tolerance on each orbit's X relative to max(F_s, |V_b|)
        [1e-12 for piecewise-constant laws, 1e-9 otherwise].

    Returns
    -------
    ContinuationResult
        The equilibrium branch, the orbit branches and the bifurcations found.

    Notes
    -----
    A law with internal state is continued on its whole state by
    ``stateful_continuation.stateful_continuation`` (``returns`` 1, no
    ``sweep``).
    """
    check.instance("model", model, BeltOscillator, "a BeltOscillator")
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")
    start, stop = check.number("start", start), check.number("stop", stop)
    s = merged(ContinuationSettings, settings, options, "continuation")
    if friction.stick_rule == "state":  # internal states: steady sliding and cycles on the whole state
        return stateful_continuation(model, friction, param, start, stop, s)
    _check(model, friction, param, (start, stop), s)
    enforce(continuation_estimate(model, friction, s))  # within the limits in force, if any
    branches: list[Branch] = []
    hopfs = _equilibria(branches, model, friction, param, np.linspace(start, stop, max(2, s.n_equilibria)), stop < start)
    problem = CycleProblem(model, friction, param, start, stop, returns=s.returns, tol=s.tol, max_period=s.max_period)
    tracer = Tracer(problem, StepControl(h0=s.step, h_max=s.max_step, max_points=s.max_points), progress=s.progress)
    found = _Found(model, friction, param, s, tracer, branches)
    found.from_hopfs(hopfs)
    found.from_ends(start, stop)
    result = ContinuationResult(
        param=param,
        start=float(start),
        stop=float(stop),
        params={**model.report(), **friction.as_dict()},
        branches=branches,
        bifurcations=sorted(found.bifs, key=lambda b: (b.value - start) / (stop - start)),
    )
    if s.sweep:
        result.sweep = brute_force_sweep(model, friction, param, np.linspace(start, stop, s.sweep), t_end=s.transient,
                                         x0=s.x0, v0=s.v0, solver=s.solver)
    return result


#: shooting runs per branch point (a bound for the corrector and the step control)
_RUNS_PER_POINT = 10


def continuation_estimate(model: BeltOscillator, friction: FrictionLaw, s: ContinuationSettings) -> Estimate:
    """The seed and sweep simulations (each to ``transient``), and ``max_points`` points of
    :data:`_RUNS_PER_POINT` orbit flows on a branch per seed (a bound: the Hopf points may be more or fewer).

    A flow's cost (:func:`~.flow.flow_cost`) is that of ``returns`` periods of ``max_period``, where a branch ends:
    a bound known before any work (the orbits' periods are found only as the branch is traced), at most
    ``hybrid.MAX_TIME``, where every flow stops.
    """
    solver = s.solver or auto_solver(friction)
    runs = 2 * ("start" in s.seeds or "stop" in s.seeds) + s.sweep
    simulations = solver.cost(model, friction, s.transient).times(runs)
    flows = float(len(s.seeds) * s.max_points * _RUNS_PER_POINT)
    span = min(s.returns * s.max_period, MAX_TIME)
    ends = Shooting(model, friction, s.returns, solver=solver)  # the shootings of the seeds' simulations
    return (Estimate(flows, f"orbit flows of up to {span:.3g} time units", flows * flow_cost(model, friction, span))
            .then(simulations).then(shooting_estimate(ends, span).times(runs - s.sweep)))


def _check(model: BeltOscillator, friction: FrictionLaw, param: str, ends: tuple[float, float], s: ContinuationSettings) -> None:
    """Refuse, before any work, an interval or settings that cannot be continued; ValueError naming what."""
    start, stop = ends
    for name, v in (("from", start), ("to", stop)):
        if not math.isfinite(v):
            raise ValueError(f"{name} must be a finite number, got {v!r}")
    tol = s.tol
    if tol is not None and not (isinstance(tol, (int, float)) and 0.0 < tol <= 1e-3):
        raise ValueError(f"tol must be a number in (0, 1e-3], got {tol!r}")
    if start == stop:
        raise ValueError(f"from and to must differ, got {start!r} twice")
    ends = [with_param(model, friction, param, v) for v in (start, stop)]
    if param in MODEL_PARAMS and all(param not in m.report() for m, _ in ends):  # e.g. omega while fex = 0
        raise ValueError(f"param {param} does not enter the autonomous system (its report: "
                         f"{', '.join(model.report())}); a forced system's: forced-continue (continue_forced)")
    for m, law in ends:
        make_flow(m, law)  # validates both ends before any work
    for seed in s.seeds:
        if seed not in SEEDS:
            raise ValueError(f"seeds must be among {', '.join(SEEDS)}, got {seed!r}")


def _equilibria(branches: list[Branch], model: BeltOscillator, friction: FrictionLaw, param: str, grid: np.ndarray,
                descending: bool) -> list[float]:
    """The Hopf points on the grid's interval; the equilibrium branch (grid and Hopf points, in the grid's order:
    ``descending`` or not) appended to ``branches``."""
    hopfs = hopf_points(model, friction, param, grid)
    values = np.array(sorted(set(grid.tolist()) | set(hopfs), reverse=descending))
    eqs = equilibrium_branch(model, friction, param, values)
    if eqs:
        pts = []
        for eq in eqs:
            m, law = with_param(model, friction, param, eq.value)
            pts.append(BranchPoint.from_equilibrium(eq, m.vb, law.fd))
        branches.append(Branch("equilibrium", pts, seed="sliding equilibrium", end="interval end"))
    return hopfs


@dataclass
class _Found:
    """The branches and bifurcations of one continuation, and the tracer that adds orbit branches to them."""

    model: BeltOscillator
    friction: FrictionLaw
    param: str
    settings: ContinuationSettings
    tracer: Tracer
    branches: list[Branch]
    bifs: list[Bifurcation] = field(default_factory=list)

    def from_hopfs(self, hopfs: list[float]) -> None:
        """A Hopf bifurcation at each point, and the branch of orbits born there unless one was traced already."""
        problem = self.tracer.p
        for lam_h in hopfs:
            detail: dict = {"criticality": None}
            self.bifs.append(Bifurcation("hopf", lam_h, 0, detail))
            if "hopf" not in self.settings.seeds or _on_branch(self.branches, lam_h, 0.0, problem, at_hopf=True):
                continue
            m, law = with_param(self.model, self.friction, self.param, lam_h)
            xi0 = 0.02 * max(abs(m.vb), 1e-6)
            begun = _start_from_hopf(self.tracer, lam_h, xi0)
            if begun is None:
                continue
            first, t = begun
            eq = equilibrium(first.model, first.law)
            # cycles beside a stable equilibrium are the unstable ones of a subcritical Hopf
            detail["criticality"] = "subcritical" if eq is not None and eq.stability == "stable" else "supercritical"
            self.add(self.tracer.trace(first, t), f"hopf at {self.param}={lam_h:.10g}")

    def from_ends(self, start: float, stop: float) -> None:
        """The branches through the attractors of simulations at the interval's ends (those not traced already)."""
        s, problem = self.settings, self.tracer.p
        for which, lam, toward in (("start", start, stop), ("stop", stop, start)):
            if which not in s.seeds:
                continue
            m, law = with_param(self.model, self.friction, self.param, lam)
            try:
                orbit = find_orbit(m, law, x0=s.x0, v0=s.v0, transient=s.transient, returns=s.returns, solver=s.solver)
            except ShootingError:
                continue  # the simulation settled on the equilibrium (or no orbit nearby)
            _, _, x_ref = problem.system(lam)
            xi = orbit.state[0] - (x_ref if math.isfinite(x_ref) else 0.0)
            if _on_branch(self.branches, lam, xi, problem):
                continue
            try:
                first, t = _start_from_orbit(self.tracer, lam, orbit.state[0], toward)
            except (RuntimeError, ValueError):
                continue
            self.add(self.tracer.trace(first, t), f"simulation at {self.param}={lam:.10g}")

    def add(self, trace: Trace, seed: str) -> None:
        """Record a traced branch (with its power flow at every point) and its events."""
        _add(self.branches, self.bifs, trace, seed, self.settings.returns, self.settings.solver)


def _start_from_hopf(tracer: Tracer, lam_h: float, xi0: float) -> tuple[Solution, np.ndarray] | None:
    """The first orbit of the branch born at lambda_H, at amplitude xi0, and the branch's tangent.

    From the virtual point (0, lambda_H) the branch leaves along xi: correct
    (xi0, lambda_H) on the line xi = xi0.
    """
    problem = tracer.p
    t0 = np.array([1.0, 0.0])
    w_h = np.array([0.0, lam_h / problem.sl])
    s = tracer.correct(w_h + (xi0 / problem.sx) * t0, t0)
    if s is None:
        return None
    return s, tracer.tangent(s, t0)


def _start_from_orbit(tracer: Tracer, lam: float, x: float, toward: float) -> tuple[Solution, np.ndarray]:
    """A solution at (lambda, X) and the tangent pointing toward lambda = ``toward``."""
    _, _, x_ref = tracer.p.system(lam)
    s = tracer.p.solve_at(lam, x - (x_ref if math.isfinite(x_ref) else 0.0))
    return s, tracer.start(s, toward)


def _point(s: Solution, returns: int, solver: Solver | None) -> BranchPoint:
    orbit = orbit_from_segment(s.model, s.law, s.seg, residual=s.G, iterations=s.iterations, returns=returns, solver=solver)
    return BranchPoint.from_orbit(s.lam, orbit)


def _add(branches: list[Branch], bifs: list[Bifurcation], trace: Trace, seed: str, returns: int, solver: Solver | None) -> None:
    """Record a traced branch (with its power flow at every point) and its events."""
    index = len(branches)
    branches.append(Branch("periodic", [_point(s, returns, solver) for s in trace.solutions], seed=seed, end=trace.end))
    for e in trace.events:
        bifs.append(Bifurcation(e.type, e.value, index, e.detail))


def _on_branch(branches: list[Branch], lam: float, xi: float, problem: CycleProblem, at_hopf: bool = False) -> bool:
    """Is (lam, xi) a point of a periodic branch already traced (or, at_hopf, where one ended on the equilibrium)?"""
    for b in branches:
        if b.kind != "periodic":
            continue
        if at_hopf:
            if b.end == "hopf" and abs(b.points[-1].value - lam) < 1e-2 * problem.sl:
                return True
            continue
        for p in b.points:
            _, _, x_ref = problem.system(p.value)
            p_xi = p.x - (x_ref if math.isfinite(x_ref) else 0.0)
            if abs(p.value - lam) <= 1e-9 * problem.sl and abs(p_xi - xi) <= 1e-6 * problem.sx:
                return True
    return False
