"""Periodic orbits by Newton shooting on a Poincare map.

The section is X' = 0 with X'' < 0 (the maxima of X).  Every periodic orbit
of this plane system winds around the sliding equilibrium at X' = 0, so it
crosses the section; a point of the section is fixed by X alone, and the
Poincare map P is a scalar map X -> X.  Its slope is the nontrivial Floquet
multiplier (the section-projected monodromy matrix, see
:meth:`~.hybrid.Segment.section_jacobian`), so Newton on P(X) - X = 0 needs
no finite differences.  With a stick phase P' = 0: P is locally constant and
Newton converges in a step or two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _validate as check
from .._display import Row, Summarized, num, pairs, system_row
from .._figures import draw
from .._json import jsonable
from ..estimate import Estimate, enforce, enforce_stage
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers.base import Solver
from ..solvers.registry import auto_solver
from ..trajectory import Trajectory
from . import floquet
from .errors import ShootingError
from .flow import Flow, flow_cost, make_flow
from .hybrid import MAX_TIME, Segment
from .measures import OrbitMeasures, measure, one_period
from .stateful import StatefulOrbit, find_stateful_orbit

#: a converged fixed point must also have |G / (x - X*)| below this (see :func:`newton`)
H_TOL = 1e-3
#: Newton gives up after this many step halvings, or this many damped steps in a row
_MAX_HALVINGS = 12
_MAX_DAMPED = 6


@dataclass(frozen=True, repr=False, eq=False)
class PeriodicOrbit(Summarized):
    """A periodic orbit, its Floquet multipliers and its power flow.

    Shows itself as a short summary; :meth:`plot` draws it.

    Attributes
    ----------
    model, friction:
        The oscillator and its law.
    state:
        (X, 0), where the orbit crosses the section X' = 0.
    period:
        Its period.
    returns:
        How many section crossings make one period (1 for a simple orbit).
    segment:
        The flow over one period: its phases and switches.
    monodromy:
        The monodromy matrix over one period (saltation matrices included).
    residual:
        |P(X) - X| at the returned X.
    iterations:
        Newton iterations taken.
    measures:
        Averages over one period, TR_B and the extremes of X and X'.
    """

    model: BeltOscillator
    friction: FrictionLaw
    state: tuple[float, float]
    period: float
    returns: int
    segment: Segment
    monodromy: np.ndarray
    residual: float
    iterations: int
    measures: OrbitMeasures

    @property
    def multipliers(self) -> np.ndarray:
        """All Floquet multipliers, the trivial one (= 1 up to rounding) included."""
        return floquet.multipliers(self.monodromy)

    @property
    def multiplier(self) -> complex:
        """The nontrivial multiplier (the slope of the Poincare map)."""
        return floquet.nontrivial(self.monodromy)

    @property
    def stability(self) -> str:
        return floquet.classify(self.multiplier)

    @property
    def stable(self) -> bool:
        return self.stability == "stable"

    @property
    def stick_fraction(self) -> float:
        return self.segment.stick_time / self.period

    @property
    def has_stick(self) -> bool:
        return self.segment.stick_time > 0.0

    @property
    def amplitude(self) -> float:
        return self.measures.amplitude

    def _summary(self) -> tuple[str, list[Row]]:
        av = self.measures.averages()
        rows = [
            system_row(self.model, self.friction),
            ("period", f"{num(self.period, 10)}" + (f" ({self.returns} section crossings)" if self.returns > 1 else "")),
            ("section", f"X={num(self.state[0], 10)}, X'=0; amplitude {num(self.amplitude)}"),
            ("stability", f"{self.stability}, multiplier {num(self.multiplier)}"),
            ("stick fraction", num(self.stick_fraction, 4)),
            ("power", pairs({k: av[k] for k in ("P_fin", "P_df", "P_dv")})),
            ("TR_B", num(self.measures.TR_B)),
            ("Newton", f"{self.iterations} iterations, residual {num(self.residual, 2)}"),
        ]
        return "PeriodicOrbit", rows

    def plot(self, path: Any = None, **options: Any):
        """Phase portrait, X(tau) and power over one period (:func:`~frictionflow.orbits.plotting.plot_orbit`).

        ``options``: the figure function's keywords (``dpi``: dots per inch, ``name``).
        """
        return draw(self, path, **options)

    def trajectory(self, dense_dt: float | None = None, solver: Solver | None = None) -> Trajectory:
        """One period integrated by the package's solver (``dense_dt`` for smooth plots)."""
        return one_period(self.model, self.friction, self.state, self.period, solver=solver, dense_dt=dense_dt)

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready report (NaN becomes None, complex numbers [re, im])."""
        seg = self.segment
        return jsonable(
            {
                "params": {**self.model.report(), **self.friction.as_dict()},
                "state": {"X": self.state[0], "V": self.state[1]},
                "period": self.period,
                "returns": self.returns,
                "floquet_multipliers": [complex(m) for m in self.multipliers],
                "multiplier": self.multiplier,
                "stable": self.stable,
                "stability": self.stability,
                "stick_fraction": self.stick_fraction,
                "has_stick": self.has_stick,
                "amplitude": self.amplitude,
                "extremes": self.measures.extremes,
                "averages": self.measures.averages(),
                "TR_B": self.measures.TR_B,
                "energy_residual": self.measures.power.energy_residual,
                "monodromy": self.monodromy,
                "phases": [{"mode": p.mode, "duration": p.duration} for p in seg.phases],
                "switches": [{"kind": s.kind, "t": s.t, "from": s.before, "to": s.after} for s in seg.switches],
                "newton": {"iterations": self.iterations, "residual": self.residual},
            }
        )


def contraction(mu: float) -> float:
    """min(1, |1 - mu|): how much smaller than the error in X the residual G = P(X) - X is.

    Near a Hopf point or a fold (mu -> 1) a small residual is not yet a small
    error: Newton's tolerance on G is scaled by this so that X is within it.
    """
    return min(1.0, abs(1.0 - mu)) if math.isfinite(mu) else 1.0


def default_tol(friction: FrictionLaw) -> float:
    """Newton tolerance relative to the orbit's scale: rounding for closed forms, ~100 rtol for solve_ivp."""
    return 1e-12 if friction.piecewise_constant else 1e-9


def _scale(model: BeltOscillator, friction: FrictionLaw) -> float:
    return max(friction.fs, abs(model.vb), 1e-12)


def poincare(flow: Flow, x: float, returns: int = 1) -> tuple[Segment, float, float]:
    """(segment, P(x), P'(x)) of the section map from (x, 0)."""
    seg = flow.run((x, 0.0), returns=returns)
    return seg, float(seg.y1[0]), float(seg.section_jacobian()[0, 0])


def _map(flow: Flow, x: float, returns: int) -> tuple[Segment | None, float, float]:
    """(segment or None, P(x), P'(x)): the compiled engine's map alone, without phases or work integrals."""
    fast = getattr(flow, "poincare", None)
    if fast is not None:
        px, dp, _, _ = fast(x, returns)
        return None, px, dp
    return poincare(flow, x, returns)


def newton(
    flow: Flow, x: float, *, x_star: float = math.nan, returns: int = 1, tol_abs: float, max_iter: int = 40
) -> tuple[float, Segment, float, int]:
    """Solve G(x) = P(x) - x = 0 by Newton with backtracking; returns (x, segment, G, iterations).

    The sliding equilibrium X* is a trivial fixed point of P (a zero-amplitude
    "orbit") that Newton would happily converge to near a Hopf point.  It is
    deflated: Newton runs on H = G / (x - X*), whose step is
    -G / (P' - 1 - G / (x - X*)), and which does not vanish at X* (there
    H = mu_eq - 1).  ``x_star`` NaN switches deflation off.
    """

    def merit(g: float, xx: float) -> float:
        if not math.isfinite(x_star):
            return abs(g)
        return abs(g / (xx - x_star)) if xx != x_star else math.inf

    def done(seg, x, r, it):
        if seg is None:
            seg = flow.run((x, 0.0), returns=returns)
            r = float(seg.y1[0]) - x
        return x, seg, r, it

    seg, px, dp = _map(flow, x, returns)
    r = px - x
    damped = 0
    for it in range(max_iter + 1):
        # |G| small only because x crept onto X* is no orbit: H must be small too
        near = abs(r) <= tol_abs and (not math.isfinite(x_star) or merit(r, x) <= H_TOL)
        if near and abs(r) <= tol_abs * contraction(dp):  # the error in X, |G / (1 - P')|, is within tol_abs
            return done(seg, x, r, it)
        if it == max_iter:
            if near:  # as close as rounding lets a barely contracting map come
                return done(seg, x, r, it)
            break
        g = dp - 1.0 - (r / (x - x_star) if math.isfinite(x_star) else 0.0)
        if not math.isfinite(g) or g == 0.0:
            raise ShootingError(f"the Poincare map has slope {dp:.6g} at X={x:.10g}: Newton cannot proceed (a fold, or a family of neutral orbits)")
        step = -r / g
        lam = 1.0
        m0 = merit(r, x)
        for _ in range(_MAX_HALVINGS):  # backtrack until the merit falls
            xn = x + lam * step
            try:
                segn, pn, dpn = _map(flow, xn, returns)
                rn = pn - xn
                mn = merit(rn, xn)
            except RuntimeError:
                mn = math.inf
            if mn < m0:
                break
            lam *= 0.5
        else:
            if near:  # the residual is at its rounding floor: X is as good as the map can tell
                return done(seg, x, r, it)
            raise ShootingError(f"Newton stalled at X={x:.10g} (residual {r:.3g}): no nearby periodic orbit")
        damped = damped + 1 if lam < 1.0 else 0
        if damped > _MAX_DAMPED and near:
            return done(seg, x, r, it)
        if damped > _MAX_DAMPED:  # creeping along without a root in sight
            raise ShootingError(f"Newton stalled at X={x:.10g} (residual {r:.3g}): no nearby periodic orbit")
        x, seg, r, dp = xn, segn, rn, dpn
    raise ShootingError(f"Newton did not converge in {max_iter} iterations (X={x:.10g}, residual {r:.3g})")


def shoot(
    model: BeltOscillator,
    friction: FrictionLaw,
    x_guess: float,
    *,
    returns: int = 1,
    tol: float | None = None,
    max_iter: int = 40,
    flow: Flow | None = None,
    solver: Solver | None = None,
) -> PeriodicOrbit:
    """The periodic orbit through (X, 0) near ``x_guess`` on the section."""
    check_shooting(0.0, tol, returns, max_iter)
    flow = make_flow(model, friction) if flow is None else flow
    scale = _scale(model, friction)
    tol_abs = (default_tol(friction) if tol is None else tol) * scale
    x_star = friction.sliding_equilibrium(model.vb)
    x, seg, r, it = newton(flow, float(x_guess), x_star=x_star, returns=returns, tol_abs=tol_abs, max_iter=max_iter)
    orbit = orbit_from_segment(model, friction, seg, residual=r, iterations=it, returns=returns, solver=solver)
    if orbit.amplitude < 1e-9 * scale:
        raise ShootingError(f"shooting converged onto the sliding equilibrium X={x:.10g}: no periodic orbit near this start")
    return orbit


def orbit_from_segment(
    model: BeltOscillator,
    friction: FrictionLaw,
    seg: Segment,
    *,
    residual: float,
    iterations: int,
    returns: int = 1,
    solver: Solver | None = None,
) -> PeriodicOrbit:
    """The :class:`PeriodicOrbit` whose one period is ``seg`` (a converged fixed point of P)."""
    state = (float(seg.y0[0]), 0.0)
    return PeriodicOrbit(
        model=model,
        friction=friction,
        state=state,
        period=seg.duration,
        returns=returns,
        segment=seg,
        monodromy=seg.jacobian(),  # the time-T map at the fixed point
        residual=float(residual),
        iterations=iterations,
        measures=measure(model, friction, state, seg.duration, solver=solver),
    )


def check_shooting(transient: float, tol: float | None, returns: int, max_iter: int, name: str = "transient") -> None:
    """One line for a shooting setting out of range (every shooting function's, single mass or structure)."""
    if check.number(name, transient, "a finite number >= 0") < 0:  # numpy scalars too; no bool, text or None
        raise ValueError(f"{name} must be a finite number >= 0, got {transient!r}")
    if tol is not None and not 0.0 < check.number("tol", tol, "in (0, 1e-3]") <= 1e-3:
        raise ValueError(f"tol must be in (0, 1e-3], got {tol!r}")
    if isinstance(returns, bool) or not isinstance(returns, (int, np.integer)) or not 1 <= returns <= 64:
        raise ValueError(f"returns must be an integer in [1, 64], got {returns!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")


def find_orbit(
    model: BeltOscillator,
    friction: FrictionLaw,
    *,
    x0: float | None = None,
    v0: float | None = None,
    transient: float = 500.0,
    returns: int = 1,
    tol: float | None = None,
    max_iter: int = 40,
    solver: Solver | None = None,
) -> PeriodicOrbit | StatefulOrbit:
    """Find a periodic orbit from a start state, after an optional transient.

    Parameters
    ----------
    model, friction:
        The oscillator and its law.
    x0, v0:
        Start state (default X = F_d, X' = V_b, as :func:`frictionflow.simulate`).
    transient:
        First simulate this long from the start (> 0: converge towards an
        attractor, 0: shoot straight from the start, a guess of an unstable
        orbit).  The state is then carried to the section, where Newton starts.
    returns:
        Section crossings per period (2 for a period-2 orbit, ...).
    tol:
        Newton tolerance on P(X) - X relative to max(F_s, |V_b|).
    max_iter:
        Newton iterations before giving up (:class:`ShootingError`).
    solver:
        Solver for the transient and for the power-flow period
        (default: exact for piecewise-constant laws, else adaptive).

    Notes
    -----
    A law with internal state (LuGre, Dahl, elasto-plastic, ...) is shot on
    its whole state by :func:`~frictionflow.orbits.find_stateful_orbit`, which returns a
    :class:`~.stateful.StatefulOrbit`.
    Inside :func:`frictionflow.estimate.limited` the transient is estimated
    before it runs and the shooting once the transient has found its period
    (``shooting_estimate`` over ``section_span``), each refused
    (ValueError) above the limits; without a transient, the shooting is
    estimated before any work, each flow bounded by ``hybrid.MAX_TIME``.
    """
    check.instance("model", model, BeltOscillator, "a BeltOscillator")
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")
    check_shooting(transient, tol, returns, max_iter)
    x0, v0 = (None if u is None else check.number(n, u) for n, u in (("x0", x0), ("v0", v0)))
    if friction.stick_rule == "state":  # internal states (LuGre, ...): Newton on the whole state
        return find_stateful_orbit(model, friction, x0=x0, v0=v0, transient=transient, returns=returns, tol=tol,
                                   max_iter=max_iter, solver=solver)
    x, v = (float(u) for u in friction.start(model.vb, x0, v0))
    flow = make_flow(model, friction)  # refuses laws it cannot differentiate, before any work
    shooting = Shooting(model, friction, returns, max_iter, solver)
    if transient > 0:  # the shooting's period is the transient's to find: estimated once it has
        enforce(lambda: (solver or auto_solver(friction)).cost(model, friction, transient), open_stage="shooting")
        traj = simulate(model, friction, solver, t_end=transient, x0=x, v0=v)
        enforce_stage("shooting", lambda: shooting_estimate(shooting, section_span(traj, returns)))
        x, v = float(traj.x[-1]), float(traj.v[-1])
    else:  # no period known: every flow stops at MAX_TIME
        enforce(lambda: shooting_estimate(shooting, MAX_TIME))
    x_star = friction.sliding_equilibrium(model.vb)
    if abs(x - x_star) + abs(v) <= 1e-9 * _scale(model, friction):
        raise ShootingError(f"the start (X={x:.10g}, X'={v:.3g}) is the sliding equilibrium: no orbit to follow from it")
    try:
        guess = flow.run((x, v), returns=1).y1[0]
    except RuntimeError as e:
        raise ShootingError(f"from X={x:.10g}, X'={v:.10g} the motion never reaches the section X' = 0: {e}") from None
    return shoot(model, friction, guess, returns=returns, tol=tol, max_iter=max_iter, flow=flow, solver=solver)


@dataclass(frozen=True)
class Shooting:
    """What a shooting's cost depends on besides its period: the system, section crossings per period, Newton's
    iterations and the solver of the period whose power flow is measured."""

    model: BeltOscillator
    friction: FrictionLaw
    returns: int = 1
    max_iter: int = 40
    solver: Solver | None = None


def shooting_flows(max_iter: int) -> float:
    """Flows a Newton shooting of ``max_iter`` iterations makes: each iteration's map and one halving of its step,
    the flow to the section before Newton and the fixed point's segment after it.  A bound unless backtracking
    halves the steps more than once an iteration on average (it may halve one step up to 12 times)."""
    return 2.0 * (max_iter + 1) + 2.0


def shooting_estimate(shooting: Shooting, span: float) -> Estimate:
    """The cost of a Newton shooting whose flows each run at most ``span`` time units (their ``returns`` section
    crossings), then the orbit's period (as long as a flow) by its solver, for the power flow.

    Parameters
    ----------
    shooting:
        The system and the shooting's settings.
    span:
        A bound on one flow's length (e.g. ``section_span``; at most ``hybrid.MAX_TIME``).
    """
    span = min(span, MAX_TIME)
    flows = shooting_flows(shooting.max_iter)
    seconds = flows * flow_cost(shooting.model, shooting.friction, span)
    period = (shooting.solver or auto_solver(shooting.friction)).cost(shooting.model, shooting.friction, span)
    return Estimate(flows, f"orbit flows of up to {span:.3g} time units", seconds).then(period)


#: the flows of Newton's iterates are held to this many times the span the transient ended with: the iterates are
#: near its attractor, whose period the transient has nearly found
SPAN_MARGIN = 2.0


def section_span(traj: Trajectory, returns: int = 1) -> float:
    """A bound on the length of a shooting's flows after the transient ``traj``: :data:`SPAN_MARGIN` times the time
    of its last ``returns`` returns to the section X' = 0 (X' falling through zero), or ``hybrid.MAX_TIME``
    (where every flow stops) if it crossed fewer times."""
    v = np.asarray(traj.v)
    down = np.flatnonzero((v[:-1] > 0.0) & (v[1:] <= 0.0)) + 1
    if len(down) <= returns:
        return MAX_TIME
    t = np.asarray(traj.t)
    return min(MAX_TIME, SPAN_MARGIN * float(t[down[-1]] - t[down[-1 - returns]]))
