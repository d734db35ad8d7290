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

import numpy as np

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..solvers.base import Solver
from .branches import Bifurcation, Branch, BranchPoint, ContinuationResult
from .cycle_problem import CycleProblem, Solution
from .equilibria import equilibrium, equilibrium_branch, hopf_points
from .flow import make_flow
from .parameters import with_param
from .shooting import ShootingError, find_orbit, orbit_from_segment
from .brute_force import sweep as brute_force_sweep
from .tracing import StepControl, Trace, Tracer

SEEDS = ("hopf", "start", "stop")


def continuation(
    model: BeltOscillator,
    friction: FrictionLaw,
    param: str,
    start: float,
    stop: float,
    *,
    seeds: tuple[str, ...] = SEEDS,
    transient: float = 500.0,
    n_equilibria: int = 101,
    max_points: int = 300,
    max_period: float = 500.0,
    step: float = 0.02,
    max_step: float = 0.1,
    returns: int = 1,
    sweep: int = 0,
    solver: Solver | None = None,
    x0: float | None = None,
    v0: float | None = None,
    tol: float | None = None,
) -> ContinuationResult:
    """Continue equilibria and periodic orbits in ``param`` from ``start`` to ``stop``.

    Parameters
    ----------
    param:
        zeta, vb, or a parameter of the friction law (fd, fs, vd, vs, delta, viscous).
    seeds:
        Where orbit branches start: ``hopf`` (every Hopf point in the
        interval), ``start``/``stop`` (the attractor a simulation of
        ``transient`` time units reaches at that end).
    n_equilibria:
        Grid points of the equilibrium branch (Hopf points are added to it).
    max_points, max_period:
        A branch stops after this many points, or once its period exceeds
        ``max_period`` (reported as a ``period_blowup``).
    step, max_step:
        First and largest arclength step, in units of the interval length
        (and of max(F_s, |V_b|) along X).
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
    """
    for name, v in (("from", start), ("to", stop)):
        if not math.isfinite(v):
            raise ValueError(f"{name} must be a finite number, got {v!r}")
    if tol is not None and not (isinstance(tol, (int, float)) and 0.0 < tol <= 1e-3):
        raise ValueError(f"tol must be a number in (0, 1e-3], got {tol!r}")
    if start == stop:
        raise ValueError(f"from and to must differ, got {start!r} twice")
    for v in (start, stop):
        make_flow(*with_param(model, friction, param, v))  # validates both ends before any work
    for s in seeds:
        if s not in SEEDS:
            raise ValueError(f"seeds must be among {', '.join(SEEDS)}, got {s!r}")

    branches: list[Branch] = []
    bifs: list[Bifurcation] = []

    # 1. equilibria and Hopf points
    grid = np.linspace(start, stop, max(2, n_equilibria))
    hopfs = hopf_points(model, friction, param, grid)
    values = np.array(sorted(set(grid.tolist()) | set(hopfs), reverse=stop < start))
    eqs = equilibrium_branch(model, friction, param, values)
    if eqs:
        pts = []
        for eq in eqs:
            m, law = with_param(model, friction, param, eq.value)
            pts.append(BranchPoint.from_equilibrium(eq, m.vb, law.fd))
        branches.append(Branch("equilibrium", pts, seed="sliding equilibrium", end="interval end"))

    problem = CycleProblem(model, friction, param, start, stop, returns=returns, tol=tol, max_period=max_period)
    tracer = Tracer(problem, StepControl(h0=step, h_max=max_step, max_points=max_points))

    # 2. orbits born at Hopf points
    for lam_h in hopfs:
        detail: dict = {"criticality": None}
        bifs.append(Bifurcation("hopf", lam_h, 0, detail))
        if "hopf" not in seeds or _on_branch(branches, lam_h, 0.0, problem, at_hopf=True):
            continue
        m, law = with_param(model, friction, param, lam_h)
        xi0 = 0.02 * max(abs(m.vb), 1e-6)
        begun = _start_from_hopf(tracer, lam_h, xi0)
        if begun is None:
            continue
        first, t = begun
        eq = equilibrium(first.model, first.law)
        # cycles beside a stable equilibrium are the unstable ones of a subcritical Hopf
        detail["criticality"] = "subcritical" if eq is not None and eq.stability == "stable" else "supercritical"
        _add(branches, bifs, tracer.trace(first, t), f"hopf at {param}={lam_h:.10g}", returns, solver)

    # 3. orbits through the attractors of simulations at the ends
    for which, lam, toward in (("start", start, stop), ("stop", stop, start)):
        if which not in seeds:
            continue
        m, law = with_param(model, friction, param, lam)
        try:
            orbit = find_orbit(m, law, x0=x0, v0=v0, transient=transient, returns=returns, solver=solver)
        except ShootingError:
            continue  # the simulation settled on the equilibrium (or no orbit nearby)
        _, _, x_ref = problem.system(lam)
        xi = orbit.state[0] - (x_ref if math.isfinite(x_ref) else 0.0)
        if _on_branch(branches, lam, xi, problem):
            continue
        try:
            first, t = _start_from_orbit(tracer, lam, orbit.state[0], toward)
        except (RuntimeError, ValueError):
            continue
        _add(branches, bifs, tracer.trace(first, t), f"simulation at {param}={lam:.10g}", returns, solver)

    result = ContinuationResult(
        param=param,
        start=float(start),
        stop=float(stop),
        params={**model.report(), **friction.as_dict()},
        branches=branches,
        bifurcations=sorted(bifs, key=lambda b: (b.value - start) / (stop - start)),
    )
    if sweep:
        result.sweep = brute_force_sweep(model, friction, param, np.linspace(start, stop, sweep), t_end=transient, x0=x0, v0=v0, solver=solver)
    return result


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
