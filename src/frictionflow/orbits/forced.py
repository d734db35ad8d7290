"""Periodic orbits of the forced oscillator: shooting, Floquet multipliers, continuation and bifurcations.

>>> from frictionflow import BeltOscillator, Coulomb
>>> from frictionflow.orbits.forced import find_forced_orbit
>>> o = find_forced_orbit(BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.0), Coulomb(0.5, 1.0), m=3)
>>> o.stable, o.has_stick, float(abs(o.multipliers[1]))   # a stick phase: one multiplier is 0
(True, True, 0.0)

With F_ex cos(Omega tau + phi) acting, a periodic orbit of period
m 2 pi / Omega (m = 1 harmonic, m > 1 subharmonic) is a fixed point of the
m-th power of the stroboscopic map P -> Phi_{2 pi / Omega}(P), P = (X, X') at
the forcing phase tau = 0 (mod 2 pi / Omega).  Its period is fixed by the
forcing, so the shooting problem is

    G(P) = Phi_{m 2 pi / Omega}(P) - P = 0,    dG/dP = M - I,

with M the monodromy matrix: the flow map's Jacobian, integrated with the
state by :func:`frictionflow.core.forced_map.flow_map` (RK4 inside the
phases, every switch located, a saltation matrix across each).  Both
eigenvalues of M are Floquet multipliers of the (X, X') part -- unlike the
autonomous system, the time direction is not among them (the extended phase
space's trivial multiplier 1 belongs to the forcing phase).  A stick phase
makes M of rank 1 (the stick onset forgets X' perturbations): one multiplier
is then exactly 0.  Unlike the autonomous (planar) system, a real multiplier
can pass through -1 (period doubling) and a complex pair through the unit
circle (Neimark-Sacker).

:func:`continue_forced` follows the fixed points in (P, lambda), lambda =
Omega or F_ex, by pseudo-arclength continuation in scaled coordinates (:class:`~.tracing.Tracer`),
with dPhi/dlambda by central differences (the period itself depends on
Omega: Phi is rerun over m 2 pi / (Omega +- delta)), and finds between
accepted points, each refined to ~1e-8 in lambda:

``fold``
    lambda turns back along the branch (the tangent's lambda component
    changes sign; on a smooth piece a multiplier passes +1);
``period_doubling``
    a real multiplier passes -1 (det(M + I) changes sign);
    :func:`switch_period_doubling` continues the 2m branch born there;
``neimark_sacker``
    a complex pair passes the unit circle (det M = |mu|^2 passes 1);
``grazing``
    the switch sequence over a period changes (a stick phase appears or
    vanishes, a slip reversal appears or vanishes): the orbit's smallest
    interior |V_r| or its shortest stick phase has reached 0.  Found by
    bisection on the sequence.  A branch ends at a grazing where the map
    jumps: a stick phase's held force touches F_s inside it, or a
    break-away turns tangent (:meth:`_Problem.locate_breakaway`).

Every point carries the multipliers, stability, amplitude (X_max -
X_min) / 2, the power averages over one orbit period (the work integrals of
the same flow-map run: :func:`frictionflow.core.forced_map.flow_map`),
TR_B = max|X + 2 zeta X'| / F_ex and the energy residual of the period's
power balance, Delta(K + U) = W_fin - W_fout + W_ex - W_dv (0 over a period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from .. import _validate as check
from .. import quantities as Q
from .._display import Row, Summarized, num, pairs, system_row
from .._json import jsonable
from ..core import forced_map as fm
from ..core import tangent
from ..estimate import Estimate, enforce, located_run
from ..friction.base import STICK_RULE_WORDS, FrictionLaw
from ..friction.registry import tangent_law_names
from ..params import FEX, OMEGA, BeltOscillator
from ..solvers.auto import auto_solver
from ..solvers.base import kernel_params, rk4_steps
from ..analysis.steady_state import stick_fraction
from .measures import measures_of, one_period
from .settings import CONTINUATION_RANGES, DEFAULT_STEPS, FORCED_RANGES, MAX_POINTS, ForcedContinuationSettings, merged
from .tracing import ContinuationProblem, Corrector, Crossing, StepControl, Step, Stop, Tracer

#: forcing periods of the transient that gives the first guess
DEFAULT_TRANSIENT = 200
#: |mu| within this of 1 is neutral
NEUTRAL_TOL = 1e-7
PARAMETERS = ("omega", "fex")
#: the declarations the continuation parameters are checked by
CONTINUED = {"omega": OMEGA, "fex": FEX}
SWITCH_NAMES = ("stick_onsets", "slip_onsets", "slip_reversals", "held_at_limit", "grazing_touches")
#: refine special points to this (absolute, in lambda)
LAMBDA_TOL = 1e-8
#: a break-away margin (:meth:`_Problem.margins`) below which the branch looks for its tangent break-away ahead
BREAKAWAY_NEAR = 0.02


class ForcedShootingError(RuntimeError):
    """Newton shooting did not converge to a forced periodic orbit."""


# -- the map ------------------------------------------------------------------------------------------------------
@dataclass
class MapRun:
    """One run of the flow map over m forcing periods from ``start`` (see :func:`frictionflow.core.forced_map.flow_map`)."""

    start: np.ndarray
    end: np.ndarray
    monodromy: np.ndarray
    work: np.ndarray
    stats: np.ndarray
    sticks: np.ndarray
    counts: np.ndarray
    span: float

    @property
    def residual(self) -> np.ndarray:
        return self.end - self.start


def _check_law(friction: FrictionLaw) -> None:
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")  # a TypeError naming it, not an AttributeError
    if friction.stick_rule != "switch":
        raise ValueError(f"friction: forced periodic orbits need a law with Coulomb's stick rule "
                         f"({', '.join(tangent_law_names())}); {friction.name} has {STICK_RULE_WORDS[friction.stick_rule]}")
    if not friction.has_tangent_kernel:
        raise ValueError(f"friction: forced periodic orbits need a compiled slip law ({', '.join(tangent_law_names())}); "
                         f"{friction.name} has no tangent kernel")


def _check_model(model: BeltOscillator) -> None:
    check.instance("model", model, BeltOscillator, "a BeltOscillator")  # a TypeError naming it, not an AttributeError
    model.refuse_moving_belt("forced periodic orbits")
    if not model.forced:
        raise ValueError("fex must be > 0 for a forced periodic orbit (the forcing amplitude), got 0")


def _check_measurable(model: BeltOscillator, friction: FrictionLaw) -> None:
    """Refuse, before any run, a forcing that the solver measuring the orbit (simulate's, over one period:
    :func:`.measures.one_period`) cannot run, with its reason (the exact solver: undamped resonance).

    Found only after the transient, it came out as that solver's refusal of the grown state as an x0 the caller
    never gave.
    """
    problem = auto_solver(friction, model).forcing_problem(model.zeta, model.omega, model.fex)
    if problem:
        raise ValueError(problem)


def _check_int(name: str, value: Any, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r}")
    return int(value)


def _given_steps(steps: Any) -> int | None:
    """``steps`` checked by its range, or None (the default: ``solvers.base.rk4_steps``)."""
    return None if steps is None else FORCED_RANGES["steps"].check(steps)


def branch_steps(base: BeltOscillator, parameter: str, interval: tuple[float, float], steps: Any) -> int:
    """RK4 steps per forcing period of a branch over ``interval`` (``steps`` if given): the default fits the
    slowest forcing the branch meets (the grid is one along the branch)."""
    slowest = min(interval) if parameter == "omega" else base.omega
    return rk4_steps(2.0 * math.pi / slowest, _given_steps(steps))


def _check_tol(tol: Any) -> float:
    """Newton's relative tolerance: a finite number > 0 (a ValueError naming tol otherwise)."""
    x = check.number("tol", tol, "a finite number > 0")
    if x <= 0:
        raise ValueError(f"tol must be a finite number > 0, got {tol!r}")
    return x


def flow_run(model: BeltOscillator, friction: FrictionLaw, state: Sequence[float], m: int = 1,
             steps: int = DEFAULT_STEPS) -> MapRun:
    """Phi over m forcing periods from ``state`` = (X, X') at tau = 0, with M, the work integrals and the extremes."""
    p = kernel_params(model, friction)
    span = m * model.forcing_period
    out = fm.map_out()
    x0 = float(state[0])
    v0 = _snap(float(state[1]), float(model.vb), x0)
    status, n_sticks = fm.flow_map(x0, v0, float(model.zeta), float(model.vb), p, span, int(m * steps), out)
    if status == fm.ZERO_PHASES:
        raise RuntimeError("the motion is caught switching without moving (repeated zero-length phases)")
    if status == fm.NOT_FINITE or not np.all(np.isfinite(out.end)):
        raise RuntimeError("the flow map left the floating-point range")
    return MapRun(np.array([x0, v0]), out.end, out.mono, out.work, out.stats,
                  out.sticks[:min(n_sticks, fm.MAX_STICKS)].copy(), out.counts, span)


def _snap(v: float, vb: float, x: float) -> float:
    """X' within rounding (1e-12 of the motion's size) of V_b is V_b.

    A section point inside a stick phase lies on X' = V_b, where the map is
    discontinuous: from just above V_b the mass slips away (the kinetic force
    cannot hold what the static one did), from V_b it keeps sticking.  Newton
    updates and continuation predictors land near, not on, V_b by rounding.
    """
    return vb if abs(v - vb) <= 1e-12 * max(abs(vb), abs(x), abs(v), 1e-300) else v


def multipliers(monodromy: np.ndarray) -> np.ndarray:
    """Both Floquet multipliers, largest modulus first (complex)."""
    mu = np.linalg.eigvals(np.asarray(monodromy, dtype=float)).astype(complex)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def stability(mu: np.ndarray, tol: float = NEUTRAL_TOL) -> str:
    """``stable`` (all |mu| < 1), ``unstable`` (some |mu| > 1) or ``neutral``."""
    r = float(np.max(np.abs(mu)))
    return "stable" if r < 1.0 - tol else ("unstable" if r > 1.0 + tol else "neutral")


def stick_phases(run: MapRun) -> np.ndarray:
    """Durations of the orbit's stick phases over its period (a phase across tau = 0 counted once)."""
    s = run.sticks
    if len(s) == 0:
        return np.zeros(0)
    d = s[:, 1] - s[:, 0]
    if len(s) > 1 and s[0, 0] == 0.0 and s[-1, 1] == run.span:
        d = np.concatenate([[d[0] + d[-1]], d[1:-1]])
    return d


def signature(run: MapRun) -> tuple[int, int, int]:
    """The switch sequence's counts over the period: (stick phases, slip onsets, slip reversals)."""
    return (len(stick_phases(run)), int(run.counts[fm.C_SLIP]), int(run.counts[fm.C_REVERSAL]))


def measures(model: BeltOscillator, friction: FrictionLaw, run: MapRun) -> dict[str, Any]:
    """Amplitude, power averages, TR_B, stick fraction and energy residual of one orbit period.

    The averages, extremes, TR_B and stick fraction are those of the package's
    solver over one period from the orbit's state (closed form for
    piecewise-constant laws), as ``simulate`` finds them on the settled
    cycle: the map's fixed step does not locate the zeros of X', where
    max(P_f, 0) has its kinks, so its work integrals are only first-order
    accurate there.  The distances to grazing come from the map's run.
    """
    traj = one_period(model, friction, tuple(run.start), run.span)
    m = measures_of(traj)
    st = run.stats
    durations = stick_phases(run)
    return {
        "amplitude": m.amplitude,
        "X_min": m.extremes["X_min"],
        "X_max": m.extremes["X_max"],
        "V_min": m.extremes["V_min"],
        "V_max": m.extremes["V_max"],
        "TR_B": m.TR_B,
        "stick_fraction": stick_fraction(traj, (traj.t[0], traj.t[-1])),
        "averages": {n: getattr(m.power, n) for n in Q.FORCED_AVERAGES},
        "energy_residual": m.power.energy_residual,
        "stick_phases": len(durations),
        "shortest_stick": float(durations.min()) if len(durations) else math.nan,
        "min_gap": float(st[fm.S_GAP]),
        "hold_margin": float(st[fm.S_HOLD]),
    }


# -- the orbit ------------------------------------------------------------------------------------------------------
@dataclass(frozen=True, repr=False, eq=False)
class ForcedOrbit(Summarized):
    """A periodic orbit of the forced oscillator: a fixed point of the m-period stroboscopic map.

    Attributes
    ----------
    model, friction:
        The forced oscillator and its law.
    m:
        The period in forcing periods.
    state:
        (X, X') at the forcing phase tau = 0 (mod 2 pi / Omega).
    period:
        The orbit's period, m 2 pi / Omega.
    monodromy:
        The Jacobian of the m-period stroboscopic map at ``state``
        (saltation matrices included).
    multipliers:
        The eigenvalues of ``monodromy``, largest modulus first.
    residual:
        max|Phi(P) - P| at the returned P.
    iterations:
        Newton iterations taken.
    amplitude, X_min, X_max:
        (X_max - X_min) / 2 and the extremes of X over one period.
    V_min, V_max:
        The extremes of X' over one period.
    TR_B:
        The force transmissibility over one period (relative to F_ex).
    stick_fraction:
        The fraction of the period spent sticking.
    averages:
        The power averages over one orbit period (P_dv, P_df, P_fin, R_c,
        R_f, P_belt, P_heat, P_f, P_ex).
    energy_residual:
        The power balance's relative residual over the period.
    stick_phases:
        The number of stick phases in one period.
    shortest_stick:
        The shortest stick phase (NaN without one): a distance to grazing.
    min_gap:
        The smallest interior minimum of |V_r| inside a slip phase (inf if
        none): a distance to grazing.
    hold_margin:
        The smallest margin F_s - |held force| inside a stick phase (inf
        if none): how close sticking comes to breaking away early.
    switches:
        The switches of one period by kind.
    settings:
        How the orbit was found (steps per period, transient, tolerance,
        method).
    """

    model: BeltOscillator
    friction: FrictionLaw
    m: int
    state: np.ndarray
    period: float
    monodromy: np.ndarray
    multipliers: np.ndarray
    residual: float
    iterations: int
    amplitude: float
    X_min: float
    X_max: float
    V_min: float
    V_max: float
    TR_B: float
    stick_fraction: float
    averages: dict[str, float]
    energy_residual: float
    stick_phases: int
    shortest_stick: float
    min_gap: float
    hold_margin: float
    switches: dict[str, int]
    settings: dict[str, Any] = field(default_factory=dict)

    @property
    def stability(self) -> str:
        return stability(self.multipliers)

    @property
    def stable(self) -> bool:
        return self.stability == "stable"

    @property
    def has_stick(self) -> bool:
        return self.stick_phases > 0

    @property
    def exponents(self) -> np.ndarray:
        """The Lyapunov exponents of the orbit, log|mu| / period (-inf for a multiplier 0)."""
        with np.errstate(divide="ignore"):
            return np.log(np.abs(self.multipliers)) / self.period

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready report (complex multipliers as [re, im], non-finite values None)."""
        return jsonable({
            "params": {**self.model.as_dict(), **self.friction.as_dict()},
            "m": self.m, "period": self.period, "state": {"X": self.state[0], "V": self.state[1]},
            "residual": self.residual, "iterations": self.iterations,
            "multipliers": [complex(z) for z in self.multipliers], "moduli": np.abs(self.multipliers),
            "stability": self.stability, "amplitude": self.amplitude, "X_min": self.X_min, "X_max": self.X_max,
            "V_min": self.V_min, "V_max": self.V_max, "TR_B": self.TR_B, "stick_fraction": self.stick_fraction, "stick_phases": self.stick_phases,
            "shortest_stick": self.shortest_stick, "min_gap": self.min_gap, "hold_margin": self.hold_margin,
            "averages": self.averages,
            "energy_residual": self.energy_residual, "switches": self.switches, "settings": self.settings,
        })

    def summary(self) -> str:
        return repr(self)

    def _summary(self) -> tuple[str, list[Row]]:
        rows = [
            system_row(self.model, self.friction),
            ("forcing", f"F_ex={num(self.model.fex, 6)}, Omega={num(self.model.omega, 8)}"),
            ("period", f"{self.m} x 2 pi / Omega = {num(self.period, 8)}"),
            ("state at tau=0", f"X={num(self.state[0], 10)}, X'={num(self.state[1], 10)} (residual {num(self.residual, 2)})"),
            ("multipliers", ", ".join(num(complex(z), 8) for z in self.multipliers) + f" ({self.stability})"),
            ("amplitude", num(self.amplitude, 8)),
            ("TR_B", num(self.TR_B, 8)),
            ("stick", f"{self.stick_phases} phase(s), fraction {num(self.stick_fraction, 4)}"),
            ("averages", pairs({k: self.averages[k] for k in ("P_ex", "P_dv", "P_fin", "P_df")}, 6)),
            ("energy residual", num(self.energy_residual, 2)),
        ]
        return "ForcedOrbit", rows


def _orbit_from(model: BeltOscillator, friction: FrictionLaw, m: int, run: MapRun, iterations: int,
                settings: dict[str, Any]) -> ForcedOrbit:
    meas = measures(model, friction, run)
    mu = multipliers(run.monodromy)
    return ForcedOrbit(
        model=model, friction=friction, m=m, state=run.start.copy(), period=run.span, monodromy=run.monodromy.copy(),
        multipliers=mu, residual=float(np.max(np.abs(run.residual))), iterations=iterations,
        switches={n: int(c) for n, c in zip(SWITCH_NAMES, run.counts, strict=True)}, settings=settings, **meas,
    )


def _scale(model: BeltOscillator, friction: FrictionLaw, state: np.ndarray) -> float:
    """The size of the motion Newton's tolerance is relative to."""
    return float(max(np.max(np.abs(state)), model.fex, abs(model.vb), friction.fd, 1e-12))


def newton(model: BeltOscillator, friction: FrictionLaw, guess: Sequence[float], m: int, steps: int,
           tol: float = 1e-11, max_iter: int = 40) -> tuple[MapRun, int]:
    """Newton on Phi_m(P) - P = 0 with the Jacobian M - I, damped (halved) while |G| does not fall."""
    P = np.asarray(guess, dtype=float).copy()
    run = flow_run(model, friction, P, m, steps)
    g = float(np.max(np.abs(run.residual)))
    for k in range(max_iter):
        if g <= tol * _scale(model, friction, P):
            return run, k
        J = run.monodromy - np.eye(2)
        try:
            dP = np.linalg.solve(J, -run.residual)
        except np.linalg.LinAlgError:
            dP = np.linalg.lstsq(J, -run.residual, rcond=None)[0]
        alpha = 1.0
        for _ in range(30):
            trial = P + alpha * dP
            try:
                new = flow_run(model, friction, trial, m, steps)
            except RuntimeError:
                new = None
            if new is not None and float(np.max(np.abs(new.residual))) < g:
                break
            alpha *= 0.5
        else:
            break
        P, run = new.start.copy(), new
        g = float(np.max(np.abs(run.residual)))
    if g <= tol * _scale(model, friction, P):
        return run, max_iter
    raise ForcedShootingError(f"Newton shooting did not converge (|Phi(P) - P| = {g:.3g} at P = ({P[0]:.8g}, {P[1]:.8g}),"
                              f" m = {m}): start closer to the orbit, or try another m")


def transient(model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, periods: int,
              steps: int = DEFAULT_STEPS) -> np.ndarray:
    """The state after ``periods`` forcing periods from (x0, v0) at tau = 0."""
    if periods == 0:
        return np.array([x0, v0], dtype=float)
    return flow_run(model, friction, (x0, v0), periods, steps).end


def forced_estimate(model: BeltOscillator, periods: float, steps: int) -> Estimate:
    """Flow maps of ``model`` over ``periods`` forcing periods, ``steps`` RK4 grid steps each, switches located."""
    return located_run(float(periods) * steps, float(periods) * model.forcing_period, "map_step", model.omega)


def find_forced_orbit(
    model: BeltOscillator,
    friction: FrictionLaw,
    m: int = 1,
    x0: float | None = None,
    v0: float | None = None,
    *,
    transient_periods: int | None = None,
    steps: int | None = None,
    tol: float = 1e-11,
    max_iter: int = 40,
) -> ForcedOrbit:
    """The periodic orbit of period m 2 pi / Omega near (x0, v0), by Newton shooting.

    Parameters
    ----------
    model, friction:
        A forced oscillator (``fex`` > 0) and a law with Coulomb's stick rule.
    m:
        The period in forcing periods (1 harmonic, > 1 subharmonic).
    x0, v0:
        The start (X, X') at tau = 0.  Unless ``transient_periods`` says
        otherwise, given both they are Newton's first guess; else (missing
        ones 0) the motion runs ``DEFAULT_TRANSIENT`` forcing periods
        from them first.
    steps:
        RK4 grid steps per forcing period (switches are located whatever it is); None: 512,
        doubled while a step would exceed 2 pi / 64 (``solvers.base.rk4_steps``).
    tol:
        |Phi(P) - P| relative to the motion's scale.
    transient_periods:
        Forcing periods run from (x0, v0) before Newton starts (see ``x0, v0``).
    max_iter:
        Newton iterations before giving up (a RuntimeError saying where it stopped); an integer in [1, 10**6].

    """
    _check_model(model)
    _check_law(friction)
    _check_measurable(model, friction)
    m, steps = FORCED_RANGES["m"].check(m), rk4_steps(model.forcing_period, _given_steps(steps))
    x0, v0 = (None if value is None else check.number(name, value) for name, value in (("x0", x0), ("v0", v0)))
    if transient_periods is None:
        transient_periods = 0 if (x0 is not None and v0 is not None) else DEFAULT_TRANSIENT
    transient_periods = FORCED_RANGES["transient_periods"].check(transient_periods)
    tol, max_iter = _check_tol(tol), _check_int("max_iter", max_iter, 1, 10**6)
    # within the limits in force, if any: the transient and (a bound) max_iter Newton runs of m periods
    enforce(forced_estimate(model, transient_periods + m * max_iter, steps))
    guess = transient(model, friction, float(x0 or 0.0), float(v0 or 0.0), transient_periods, steps)
    run, iterations = newton(model, friction, guess, m, steps, tol, max_iter)
    return _orbit_from(model, friction, m, run, iterations,
                       {"steps_per_period": steps, "transient_periods": transient_periods, "tol": tol,
                        "method": "Newton shooting on the m-period stroboscopic map (RK4, located switches, saltation)"})


# -- continuation -------------------------------------------------------------------------------------------------
@dataclass(frozen=True, repr=False, eq=False)
class BranchPoint(Summarized):
    """One orbit on a branch: lambda, the state at tau = 0, the multipliers and the orbit's measures.

    The extremes, TR_B, stick fraction, averages and energy residual are those
    of the package's solver over one orbit period from ``state``; the
    distances to grazing (``shortest_stick``, ``min_gap``, ``hold_margin``)
    come from the flow map's run.

    Attributes
    ----------
    lam:
        lambda, the continued parameter's value (the branch's ``parameter``:
        Omega or F_ex).
    state:
        P = (X, X') at the forcing phase tau = 0 (mod 2 pi / Omega), shape (2,).
    multipliers:
        The Floquet multipliers, the eigenvalues of ``monodromy`` (complex),
        largest modulus first.
    amplitude, X_min, X_max:
        (X_max - X_min) / 2 and the extremes of X over one orbit period.
    V_min, V_max:
        The extremes of X' over one orbit period.
    TR_B:
        The force transmissibility over one orbit period (relative to F_ex).
    stick_fraction:
        The fraction of the orbit period spent sticking.
    averages:
        The power averages over one orbit period, by name (P_dv, P_df, P_fin,
        R_c, R_f, P_belt, P_heat, P_f, P_ex).
    energy_residual:
        The power balance's relative residual over the orbit period.
    stick_phases:
        The number of stick phases in one orbit period.
    shortest_stick:
        The duration (tau) of the shortest stick phase (NaN without one): a
        distance to grazing.
    min_gap:
        The smallest interior minimum of |V_r| inside a slip phase (inf if
        none): a distance to grazing.
    hold_margin:
        The smallest margin F_s - |held force| inside a stick phase (inf if
        none): how close sticking comes to breaking away early.
    residual:
        max|Phi(P) - P| at ``state``: how closely it is a fixed point of the
        m-period stroboscopic map.
    signature:
        The switch sequence's counts over the orbit period: (stick phases,
        slip onsets, slip reversals); a change between points is a grazing.
    monodromy:
        M, the 2 x 2 Jacobian of the m-period stroboscopic map at ``state``
        (saltation matrices included).
    """

    lam: float
    state: np.ndarray
    multipliers: np.ndarray
    amplitude: float
    X_min: float
    X_max: float
    V_min: float
    V_max: float
    TR_B: float
    stick_fraction: float
    averages: dict[str, float]
    energy_residual: float
    stick_phases: int
    shortest_stick: float
    min_gap: float
    hold_margin: float
    residual: float
    signature: tuple[int, int, int]
    monodromy: np.ndarray

    @property
    def stability(self) -> str:
        return stability(self.multipliers)

    @property
    def stable(self) -> bool:
        return self.stability == "stable"

    def as_dict(self) -> dict[str, Any]:
        return jsonable({"lambda": self.lam, "X": self.state[0], "V": self.state[1],
                         "multipliers": [complex(z) for z in self.multipliers], "stability": self.stability,
                         "amplitude": self.amplitude, "X_min": self.X_min, "X_max": self.X_max,
                         "V_min": self.V_min, "V_max": self.V_max, "TR_B": self.TR_B, "stick_fraction": self.stick_fraction, "stick_phases": self.stick_phases,
                         "averages": self.averages, "energy_residual": self.energy_residual, "residual": self.residual})

    def _summary(self) -> tuple[str, list[Row]]:
        return "BranchPoint", [("lambda", num(self.lam, 10)), ("X, X'", f"{num(self.state[0], 8)}, {num(self.state[1], 8)}"),
                               ("multipliers", ", ".join(num(complex(z), 6) for z in self.multipliers)),
                               ("stability", self.stability)]


@dataclass(eq=False)
class BranchEvent:
    """A special point between two accepted points of a branch, refined to ~1e-8 in lambda.

    Each field below is kept as the attribute of the same name.

    Parameters
    ----------
    type:
        ``fold``, ``period_doubling``, ``neimark_sacker``, ``grazing``,
        ``branch_end`` (the corrector fails beyond the last point, with no
        grazing near) or ``branch_point`` (the first event of a period-doubled
        branch: the period doubling it was born at, with that point's state
        and multipliers on the parent branch).
    lam:
        lambda, the continued parameter's value at the event (for a grazing
        found by bisection the middle of its final bracket; for one that
        ends the branch, extrapolated from the last points where it could be).
    state:
        P = (X, X') at tau = 0 of the orbit at the event (for a grazing, of
        the orbit next to it, or extrapolated), shape (2,).
    multipliers:
        The Floquet multipliers there, the eigenvalues of ``monodromy``
        (complex), largest modulus first.
    detail:
        What else is known, by name (in the JSON beside type, lambda, X, V).
        A fold, period doubling or Neimark-Sacker point: ``refined`` (whether
        the secant search converged; else the point is the later accepted
        orbit); a fold also ``smooth`` (a multiplier passes +1; False at a
        grazing corner), a Neimark-Sacker point ``angle`` (arg mu of the
        complex pair, radians).  A grazing: the switch-sequence signatures
        ``before`` and ``after``, whether a ``stick_phase`` or a
        ``slip_reversal`` ``appears`` or ``vanishes``, the bisection's
        ``lambda_bracket``, ``corner`` where the branch was continued past
        it; where it ends the branch, ``at`` (which margin reached 0:
        ``stick_splits``, ``stick_appears``, ``stick_vanishes`` or
        ``breakaway_tangent``), ``margin_at_last_point``, ``extrapolated``
        or ``refined``, and ``ends_branch``.  A branch end: ``reason`` and the ``margins`` at
        the last point.  A branch point: ``from``.
    monodromy:
        The 2 x 2 Jacobian of the m-period stroboscopic map there, or None
        (a ``branch_point`` carries none).
    """

    type: str
    lam: float
    state: np.ndarray
    multipliers: np.ndarray
    detail: dict[str, Any] = field(default_factory=dict)
    monodromy: np.ndarray | None = None

    def as_dict(self) -> dict[str, Any]:
        return jsonable({"type": self.type, "lambda": self.lam, "X": self.state[0], "V": self.state[1],
                         "multipliers": [complex(z) for z in self.multipliers], **self.detail})


@dataclass(frozen=True, repr=False, eq=False)
class ForcedBranch(Summarized):
    """A branch of forced periodic orbits of period m 2 pi / Omega in lambda = Omega or F_ex.

    Attributes
    ----------
    model, friction:
        The forced oscillator (at the first orbit's parameter value) and its law.
    parameter:
        lambda: ``omega`` or ``fex``.
    m:
        The orbits' period in forcing periods.
    points:
        The orbits found, in the order traced (lambda, state, multipliers, measures).
    events:
        The special points between them (fold, period doubling,
        Neimark-Sacker, grazing), refined to ~1e-8 in lambda.
    end:
        Why the branch stopped (left the interval, failed to continue, ``max_points``).
    settings:
        How it was traced (:class:`~.settings.ForcedContinuationSettings`'s fields).
    """

    model: BeltOscillator
    friction: FrictionLaw
    parameter: str
    m: int
    points: list[BranchPoint]
    events: list[BranchEvent]
    end: str
    settings: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.points)

    @property
    def lam(self) -> np.ndarray:
        return np.array([p.lam for p in self.points])

    @property
    def amplitude(self) -> np.ndarray:
        return np.array([p.amplitude for p in self.points])

    @property
    def x(self) -> np.ndarray:
        """The stroboscopic X (at tau = 0) along the branch."""
        return np.array([p.state[0] for p in self.points])

    @property
    def stable(self) -> np.ndarray:
        return np.array([p.stable for p in self.points])

    def events_of(self, kind: str) -> list[BranchEvent]:
        return [e for e in self.events if e.type == kind]

    def model_at(self, lam: float) -> BeltOscillator:
        return replace(self.model, **{self.parameter: float(lam)})

    def as_dict(self) -> dict[str, Any]:
        return jsonable({"params": {**self.model.as_dict(), **self.friction.as_dict()}, "parameter": self.parameter,
                         "m": self.m, "end": self.end, "points": [p.as_dict() for p in self.points],
                         "events": [e.as_dict() for e in self.events], "settings": self.settings})

    def summary(self) -> str:
        return repr(self)

    def _summary(self) -> tuple[str, list[Row]]:
        lam = self.lam
        rows = [system_row(self.model, self.friction),
                ("branch", f"m={self.m} in {self.parameter} from {num(lam[0], 6)} to {num(lam[-1], 6)}, "
                           f"{len(self.points)} points, ended: {self.end}")]
        for e in self.events:
            rows.append((e.type, f"{self.parameter}={num(e.lam, 10)}" + (f" ({pairs(e.detail)})" if e.detail else "")))
        return "ForcedBranch", rows


@dataclass
class _Sol:
    """A fixed point P of Phi_m at lambda, its map run, and dPhi/dlambda (NaN until differenced)."""

    P: np.ndarray
    lam: float
    run: MapRun
    dl: np.ndarray
    iterations: int = 0

    @property
    def u(self) -> np.ndarray:
        return np.array([self.P[0], self.P[1], self.lam])


class _Problem(ContinuationProblem):
    """Fixed points of Phi_m(.; lambda) - P in the scaled coordinates w = (X / s_x, X' / s_x, lambda / s_l).

    A :class:`~.tracing.ContinuationProblem` in the two unknowns P = (X, X')
    with lambda in ``interval``; ``scales`` = (s_x, s_l).
    """

    #: dPhi/dlambda costs two more map runs: a chord, renewed every 3 iterations and at the accepted point
    #: (the tangent, which also locates folds); Newton gives up after 3 slow iterations
    corrector = Corrector(max_iter=10, stall_after=3, chord_every=3, fresh_lambda=True)

    def __init__(self, model: BeltOscillator, friction: FrictionLaw, parameter: str, m: int, *, steps: int,
                 scales: tuple[float, float], interval: tuple[float, float], tol: float) -> None:
        self.model, self.friction, self.parameter, self.m, self.steps = model, friction, parameter, m, steps
        self.scale = np.array([scales[0], scales[0], scales[1]])
        self.lo, self.hi = min(interval), max(interval)
        self.tol = tol
        self._last_exit = (math.nan, math.inf)  # (lambda, break-away margin) of the last point :meth:`stop` saw
        self._retry_below = BREAKAWAY_NEAR  # after a failed search, the margin it must halve to before the next

    def model_at(self, lam: float) -> BeltOscillator:
        return replace(self.model, **{self.parameter: float(lam)})

    def run(self, P, lam) -> MapRun:
        return flow_run(self.model_at(lam), self.friction, P, self.m, self.steps)

    def difference(self, P, lam, end: np.ndarray | None = None) -> np.ndarray:
        """dPhi/dlambda by differences (relative step 1e-6; Omega's change moves the period's end too).

        Central where both one-sided quotients agree; where they do not, a
        discontinuity of the map (a stick phase breaking) lies within the
        step, and the smaller one-sided quotient -- the side without it -- is taken.
        """
        d = 1e-6 * max(abs(lam), 1e-3)
        if end is None:
            end = self.run(P, lam).end
        fwd = (self.run(P, lam + d).end - end) / d
        bwd = (end - self.run(P, lam - d).end) / d
        if np.max(np.abs(fwd - bwd)) <= 1e-2 * max(np.max(np.abs(fwd)), np.max(np.abs(bwd))) + 1e-12:
            return 0.5 * (fwd + bwd)
        return fwd if np.max(np.abs(fwd)) < np.max(np.abs(bwd)) else bwd

    # -- the continuation protocol, unknowns u = (X, X', lambda) ----------------------------------------------------
    def evaluate(self, u: np.ndarray) -> _Sol:
        run = self.run(u[:2], u[2])
        return _Sol(run.start.copy(), float(u[2]), run, np.full(2, math.nan))  # run.start: X' snapped onto V_b

    def unknowns(self, s: _Sol) -> np.ndarray:
        return s.u

    def residual(self, s: _Sol) -> np.ndarray:
        return s.run.residual

    def jacobian(self, s: _Sol) -> np.ndarray:
        return np.column_stack([s.run.monodromy - np.eye(2), s.dl])

    def d_lambda(self, s: _Sol) -> np.ndarray:
        return self.difference(s.P, s.lam, s.run.end)

    def set_d_lambda(self, s: _Sol, column: np.ndarray) -> None:
        s.dl = column

    def converged(self, s: _Sol) -> bool:
        return float(np.max(np.abs(s.run.residual))) <= self.tol * _scale(self.model_at(s.lam), self.friction, s.run.start)

    def solve_at(self, lam: float, x: np.ndarray) -> _Sol:
        """The fixed point at a given lambda (Newton in P alone); raises ForcedShootingError (or ValueError)."""
        run, k = newton(self.model_at(lam), self.friction, x, self.m, self.steps, self.tol, 20)
        return _Sol(run.start.copy(), float(lam), run, self.difference(run.start, lam, run.end), k)

    def tests(self, s: _Sol) -> dict[str, float]:
        """det(M - I) (a multiplier +1), det(M + I) (-1: period doubling), det M - 1 (|mu| = 1 for a complex pair),
        and the discriminant of M's characteristic polynomial (< 0: a complex pair)."""
        M = s.run.monodromy
        det = float(np.linalg.det(M))
        tr = float(np.trace(M))
        return {"fold": det - tr + 1.0, "pd": det + tr + 1.0, "ns": det - 1.0, "discriminant": tr * tr - 4.0 * det}

    def admissible(self, u: np.ndarray) -> bool:
        return u[2] > 0.0  # Omega and F_ex are positive

    # -- events ---------------------------------------------------------------------------------------------------
    def events(self, tracer: Tracer, step: Step) -> list[BranchEvent]:
        """Grazing (the switch sequence changes), folds, period doublings and Neimark-Sacker points between a and b."""
        a, b, ta, tb = step.a, step.b, step.ta, step.tb
        out = []
        sa, sb = signature(a.run), signature(b.run)
        if sa != sb:
            out.append(self._grazing(tracer, step, sa, sb))
        fa, fb = self.tests(a), self.tests(b)
        complex_a, complex_b = fa["discriminant"] < 0.0, fb["discriminant"] < 0.0
        smooth_fold = fa["fold"] * fb["fold"] < 0.0
        locate = {"max_iter": 40, "xtol": 1e-13, "lam_tol": LAMBDA_TOL}
        if ta[2] * tb[2] < 0.0 and (smooth_fold or sa != sb):
            s = tracer.secant(step, lambda s: tracer.tangent(s, ta)[2], ta[2], tb[2], **locate)
            out.append(_event("fold", s or b, {"smooth": smooth_fold and sa == sb, "refined": s is not None}))
        if fa["pd"] * fb["pd"] < 0.0 and not (complex_a or complex_b):
            s = tracer.secant(step, lambda s: self.tests(s)["pd"], fa["pd"], fb["pd"], **locate)
            out.append(_event("period_doubling", s or b, {"refined": s is not None}))
        if fa["ns"] * fb["ns"] < 0.0 and complex_a and complex_b:
            s = tracer.secant(step, lambda s: self.tests(s)["ns"], fa["ns"], fb["ns"], **locate)
            out.append(_event("neimark_sacker", s or b, {"refined": s is not None}))
        return out

    def _grazing(self, tracer: Tracer, step: Step, sa, sb) -> BranchEvent:
        """Bisection on arclength for the switch-sequence change, to ~1e-8 in lambda."""
        best_a, best_b = tracer.bisect(step, lambda s: signature(s.run) == sa, max_iter=60, lam_tol=LAMBDA_TOL)
        detail = {"before": list(sa), "after": list(sb)}
        if sa[0] != sb[0]:
            detail["stick_phase"] = "appears" if sb[0] > sa[0] else "vanishes"
        if sa[2] != sb[2]:
            detail["slip_reversal"] = "appears" if sb[2] > sa[2] else "vanishes"
        detail["lambda_bracket"] = [best_a.lam, best_b.lam if best_b is not None else math.nan]
        ev = _event("grazing", best_b or best_a, detail)
        ev.lam = 0.5 * (best_a.lam + best_b.lam) if best_b is not None else best_a.lam
        return ev

    # -- where the corrector fails ----------------------------------------------------------------------------------
    def dead_end(self, tracer: Tracer, solutions: list[_Sol], t: np.ndarray) -> Crossing | Stop:
        """Past a grazing corner if the last orbit is near one (:meth:`cross_corner`), else the branch's end."""
        ev = self.diagnose(solutions)
        crossed = self.cross_corner(tracer, solutions[-1], t, ev) if ev.type == "grazing" else None
        if crossed is not None:
            return crossed
        return Stop("grazing" if ev.type == "grazing" else "the corrector fails beyond this point", True, [ev])

    def margins(self, s: _Sol) -> dict[str, float]:
        """Relative distances of the orbit to the grazings the map cannot be continued through."""
        st = s.run.stats
        durations = stick_phases(s.run)
        return {
            # the held force touches F_s inside a stick phase: it breaks in two (the map jumps if F_s > F(0+))
            "stick_splits": float(st[fm.S_HOLD]) / max(self.friction.fs, 1e-300),
            # a slip phase touches V_r = 0: a stick phase or a reversal appears
            "stick_appears": float(st[fm.S_GAP]) / self.scale[0],
            # a stick phase shrinks to nothing
            "stick_vanishes": float(durations.min()) / s.run.span if len(durations) else math.inf,
            # a break-away turns tangent (then the stick's end jumps): the held force's overshoot beyond F_s at its
            # turn after the break-away, whose square root falls linearly along the branch (the multipliers as its
            # inverse)
            "breakaway_tangent": math.sqrt(float(st[fm.S_EXIT]) / max(self.friction.fs, 1e-300)),
        }

    # -- a break-away turning tangent ends the branch, in a crawl at the smallest step ------------------------------
    def stop(self, s: _Sol) -> Stop | None:
        """The branch ends at a tangent break-away ahead of s, located (:meth:`locate_breakaway`) once s's
        break-away margin is its smallest, below :data:`BREAKAWAY_NEAR` and falling along the branch.

        Where a break-away turns tangent the orbit's multiplier grows without
        bound and no step of the tracer reaches the end: it would crawl on at
        the smallest step.
        """
        margins = self.margins(s)
        g = margins["breakaway_tangent"]
        lam_prev, g_prev = self._last_exit
        self._last_exit = (s.lam, g)
        if not (g < self._retry_below and g < g_prev and math.isfinite(lam_prev) and min(margins.values()) == g):
            return None
        ev = self.locate_breakaway(s, math.copysign(1.0, s.lam - lam_prev))
        if ev is None:
            self._retry_below = 0.5 * g
            return None
        return Stop("grazing", True, [ev])

    def locate_breakaway(self, s: _Sol, direction: float) -> BranchEvent | None:
        """lambda beyond s (going ``direction``) where its break-away turns tangent; None if it is not ahead.

        The margin falls linearly in lambda, so the secant through the last
        two orbits of s's switch sequence (:meth:`solve_at`) estimates where
        it reaches 0.  Each new orbit is taken half way there, from the
        side where the orbit exists: Newton's basin shrinks as the multiplier
        grows, and past the grazing it finds other orbits or none.
        """
        sig = signature(s.run)
        good = [(s.lam, self.margins(s)["breakaway_tangent"], s)]
        lam, est, refined = s.lam + direction * 1e-6 * self.scale[2], math.nan, False
        for _ in range(60):
            (l0, _, s0), (l1, _, s1) = good[-2:] if len(good) > 1 else (good[0], good[0])
            P = s1.P if len(good) < 2 else s1.P + (s1.P - s0.P) * (lam - l1) / (l1 - l0)
            try:
                new = self.solve_at(lam, P)
                g = self.margins(new)["breakaway_tangent"] if signature(new.run) == sig else math.nan
            except (RuntimeError, ValueError):
                g = math.nan
            if not 0.0 < g < math.inf:  # past the grazing, or outside Newton's basin: closer to the last orbit
                lam = l1 + 0.5 * (lam - l1)
                continue
            good.append((lam, g, new))
            (l0, g0, _), (l1, g1, _) = good[-2:]
            if not g1 < g0:
                return None  # the margin does not fall this way
            previous, est = est, l1 - g1 * (l1 - l0) / (g1 - g0)
            refined = abs(est - previous) <= LAMBDA_TOL * max(1.0, abs(est))
            if refined:
                break
            lam = l1 + 0.5 * (est - l1)
        if not (len(good) > 2 and (est - s.lam) * direction > 0.0 and self.lo <= est <= self.hi):
            return None  # behind s, or beyond the interval's end (which the branch reaches first)
        (l0, _, s0), (l1, g1, last) = good[-2:]
        P = last.P + (last.P - s0.P) * (est - l1) / (l1 - l0)
        return BranchEvent("grazing", float(est), P, multipliers(last.run.monodromy),
                           {"at": "breakaway_tangent", "margin_at_last_point": g1, "refined": refined, "ends_branch": True},
                           last.run.monodromy.copy())

    def cross_corner(self, tracer: Tracer, a: _Sol, t: np.ndarray, ev: BranchEvent) -> Crossing | None:
        """Step over a grazing corner of the branch, where it has no tangent.

        A slip-only orbit that touches V_r = 0 meets a stick-slip one at an
        angle (a multiplier jumps to 0), and the branch may turn back there
        (a non-smooth fold).  Next to the corner, at lambda a little beyond
        (first) or before a's, Newton at fixed lambda from a's state looks for
        an orbit with another switch sequence; the branch leaves along it, away from a.
        """
        sa = signature(a.run)
        forward = math.copysign(1.0, t[2])
        for size in (1e-6, 1e-5, 1e-4, 1e-3):
            for direction in (forward, -forward):
                lam = ev.lam + direction * size * self.scale[2]
                if not (self.lo <= lam <= self.hi):
                    continue
                try:
                    s = self.solve_at(lam, ev.state)
                except (RuntimeError, ValueError):
                    continue
                if signature(s.run) == sa:
                    continue
                t_new = tracer.tangent(s, None)
                if t_new[2] * direction < 0.0:
                    t_new = -t_new  # on along the side where the new orbit was found
                detail = {"before": list(sa), "after": list(signature(s.run)), "corner": True}
                found = [BranchEvent("grazing", ev.lam, ev.state.copy(), ev.multipliers, {**ev.detail, **detail},
                                     ev.monodromy)]
                found[0].detail.pop("ends_branch", None)
                if direction != forward:
                    found.append(BranchEvent("fold", ev.lam, ev.state.copy(), ev.multipliers,
                                             {"smooth": False, "at": "grazing"}, ev.monodromy))
                return Crossing(s, t_new, found)
        return None

    def diagnose(self, sols: list[_Sol]) -> BranchEvent:
        """Why the branch stops at its last point: a grazing (a margin near 0, extrapolated to 0) or unknown."""
        a = sols[-1]
        ma = self.margins(a)
        kind = min(ma, key=ma.get)
        mu = multipliers(a.run.monodromy)
        if not ma[kind] < 1e-3:
            return BranchEvent("branch_end", a.lam, a.P.copy(), mu, {"reason": "the corrector fails beyond this point",
                                                                    "margins": ma}, a.run.monodromy.copy())
        lam, P = a.lam, a.P.copy()
        refined = False
        if len(sols) > 1:
            b = sols[-2]
            mb = self.margins(b)[kind]
            if math.isfinite(mb) and mb != ma[kind]:
                frac = ma[kind] / (mb - ma[kind])  # linear in lambda: margin 0 this far beyond a
                if abs(frac) <= 10.0:
                    lam = a.lam + frac * (a.lam - b.lam)
                    P = a.P + frac * (a.P - b.P)
                    refined = True
        return BranchEvent("grazing", float(lam), P, mu, {"at": kind, "margin_at_last_point": ma[kind],
                                                          "extrapolated": refined, "ends_branch": True},
                           a.run.monodromy.copy())


def _event(kind: str, s: _Sol, detail: dict[str, Any]) -> BranchEvent:
    mu = multipliers(s.run.monodromy)
    if kind == "neimark_sacker":
        detail = {**detail, "angle": float(abs(np.angle(mu[0])))}
    return BranchEvent(kind, s.lam, s.P.copy(), mu, detail, s.run.monodromy.copy())


def _steps(h0: float, h_max: float, h_min: float, max_points: int, detect: bool) -> StepControl:
    """The forced tracer's step rule: halve on a 0.7 turn (not 0.5: the map's corners are sharp in two unknowns)
    or a corrector landing beyond 2 h (another branch), shrink by 0.6 after a slow corrector."""
    return StepControl(h0=h0, h_max=h_max, h_min=h_min, max_points=max_points, shrink=0.6, min_cos=0.7, turn_guard=4.0,
                       jump=2.0, detect=detect)


def _point(pb: _Problem, s: _Sol) -> BranchPoint:
    meas = measures(pb.model_at(s.lam), pb.friction, s.run)
    return BranchPoint(lam=s.lam, state=s.P.copy(), multipliers=multipliers(s.run.monodromy),
                       residual=float(np.max(np.abs(s.run.residual))), signature=signature(s.run),
                       monodromy=s.run.monodromy.copy(),
                       **{k: meas[k] for k in ("amplitude", "X_min", "X_max", "V_min", "V_max", "TR_B", "stick_fraction",
                                               "averages",
                                               "energy_residual", "stick_phases", "shortest_stick", "min_gap",
                                               "hold_margin")})


def check_parameter(parameter: str, value: float, name: str) -> float:
    """``value`` of the continuation ``parameter`` (omega or fex), checked by its declaration (its range, both
    ends of the interval alike) and > 0; ValueError starting with ``name`` (the end it is) otherwise."""
    if parameter not in PARAMETERS:
        raise ValueError(f"parameter must be one of {PARAMETERS}, got {parameter!r}")
    try:
        value = CONTINUED[parameter].check(value)
    except ValueError as e:
        raise ValueError(f"{name}: {e}") from None
    if value <= 0.0:
        raise ValueError(f"{name}: {parameter} must be > 0 (a forced orbit needs forcing), got {value!r}")
    return value


def continue_forced(
    model: BeltOscillator,
    friction: FrictionLaw,
    parameter: str = "omega",
    start: float | None = None,
    stop: float | None = None,
    *,
    m: int = 1,
    x0: float | None = None,
    v0: float | None = None,
    orbit: ForcedOrbit | None = None,
    settings: ForcedContinuationSettings | None = None,
    **options: Any,
) -> ForcedBranch:
    """Follow the m-period forced orbit in ``parameter`` (``omega`` or ``fex``) from ``start`` toward ``stop``.

    The first orbit is ``orbit`` if given, else :func:`find_forced_orbit` at
    ``start`` (default: ``model``'s value; from x0, v0 as there).  The branch
    is traced by pseudo-arclength (it passes folds) until it leaves
    [start, stop] (the last point then lies on the end), fails to continue,
    or ``max_points``.  Special points are refined to ~1e-8 in lambda (see
    the module docstring).

    ``settings`` (:class:`~.settings.ForcedContinuationSettings`) says how
    the branch is traced; its fields may also be given as keywords, which
    replace the record's (a TypeError names any other keyword):
    ``steps`` (RK4 grid steps per forcing period [512]), ``h0``, ``h_max``,
    ``h_min`` (first, largest and smallest step [0.01, 0.04, 1e-6], in scaled
    arclength: lambda over |stop - start|, the state over the first orbit's
    size), ``max_points`` [400], ``detect`` (locate the special points [True]),
    ``tol`` (Newton tolerance [1e-11]) and ``progress`` (a bar on stderr [False]).

    Parameters
    ----------
    model, friction:
        A forced oscillator (``fex`` > 0) and a law with Coulomb's stick rule.
    parameter:
        lambda: ``omega`` or ``fex``.
    start, stop:
        Where the branch starts (default: ``model``'s value) and the end it is traced toward.
    m:
        The period in forcing periods.
    x0, v0:
        The start of :func:`find_forced_orbit` when ``orbit`` is not given.
    orbit:
        The first orbit, already found.
    settings:
        How the branch is traced (above).
    **options:
        Fields of ``settings`` (above), replacing the record's.
    """
    s = merged(ForcedContinuationSettings, settings, options, "continue_forced")
    _check_model(model)
    _check_law(friction)
    if parameter not in PARAMETERS:
        raise ValueError(f"parameter must be one of {PARAMETERS}, got {parameter!r}")
    start = check_parameter(parameter, getattr(model, parameter) if start is None else start, "start")
    if stop is None:
        raise ValueError(f"stop: give the other end of the {parameter} interval")
    stop = check_parameter(parameter, stop, "stop")
    if stop == start:
        raise ValueError(f"stop must differ from start ({start!r})")
    m = FORCED_RANGES["m"].check(m)
    s = replace(s, steps=branch_steps(model, parameter, (start, stop), s.steps),
                max_points=CONTINUATION_RANGES["max_points"].check(s.max_points))  # the CLI's range too
    if not (0 < s.h_min <= s.h0 <= s.h_max):
        raise ValueError(f"steps must satisfy 0 < h_min <= h0 <= h_max, got {s.h_min!r}, {s.h0!r}, {s.h_max!r}")
    base = replace(model, **{parameter: start})
    _check_measurable(base, friction)  # a given orbit skips find_forced_orbit's check, and its points are measured too
    enforce(branch_estimate(base, parameter, (start, stop), m, s, orbit is None))  # within the limits in force
    if orbit is None:
        orbit = find_forced_orbit(base, friction, m, x0, v0, steps=s.steps, tol=s.tol)
    elif orbit.m != m or not math.isclose(getattr(orbit.model, parameter), start, rel_tol=1e-12):
        raise ValueError(f"orbit: its m ({orbit.m}) and {parameter} must be the branch's (m={m}, {parameter}={start})")
    sx = max(orbit.amplitude, float(np.max(np.abs(orbit.state))), model.fex, abs(model.vb), friction.fd, 1e-9)
    pb = _Problem(base, friction, parameter, m, steps=s.steps, scales=(sx, abs(stop - start)), interval=(start, stop), tol=s.tol)
    return _trace_forced(pb, orbit.state, (start, stop), sx, s)


#: corrector runs per branch point (a bound: :class:`_Problem`'s corrector stops at 10 iterations)
_RUNS_PER_POINT = 10


def branch_estimate(base: BeltOscillator, parameter: str, interval: tuple[float, float], m: int,
                     s: ForcedContinuationSettings, first: bool) -> Estimate:
    """The branch's flow maps: ``max_points`` points of :data:`_RUNS_PER_POINT` runs (a bound) of m periods, after
    the first orbit's transient and Newton runs (``first``).

    In omega the points are taken as spread evenly over the interval: a
    forcing period of the mean of 2 pi / omega there (an expectation, not a
    bound: a branch may crowd its points anywhere).
    """
    lo, hi = min(interval), max(interval)
    slowest = replace(base, omega=(hi - lo) / math.log(hi / lo)) if parameter == "omega" else base
    periods = s.max_points * _RUNS_PER_POINT * m + (DEFAULT_TRANSIENT + 40 * m if first else 0)
    return forced_estimate(slowest, periods, branch_steps(base, parameter, interval, s.steps))


def _trace_forced(pb: _Problem, state: np.ndarray, interval: tuple[float, float], sx: float,
                  s: ForcedContinuationSettings) -> ForcedBranch:
    """The branch of ``pb`` traced over ``interval`` from the orbit through ``state`` at its start (state scale ``sx``)."""
    (start, stop), parameter = interval, pb.parameter
    try:
        first = pb.solve_at(start, state)
    except (RuntimeError, ValueError):
        raise ForcedShootingError(f"no orbit to start from at {parameter}={start}") from None
    tracer = Tracer(pb, _steps(s.h0, s.h_max, s.h_min, s.max_points, s.detect), progress=s.progress)
    trace = tracer.trace(first, tracer.start(first, stop))
    return ForcedBranch(model=pb.model, friction=pb.friction, parameter=parameter, m=pb.m,
                        points=[_point(pb, sol) for sol in trace.solutions], events=trace.events, end=trace.end,
                        settings={"steps_per_period": s.steps, "h0": s.h0, "h_max": s.h_max, "h_min": s.h_min, "tol": s.tol,
                                  "start": start, "stop": stop, "max_points": s.max_points,
                                  "scales": {"state": sx, "lambda": abs(stop - start)}})


def switch_period_doubling(branch: ForcedBranch, event: BranchEvent | None = None, *, h: float = 0.01,
                           max_points: int | None = None, detect: bool = True) -> ForcedBranch:
    """The 2m branch born at a period doubling of ``branch`` (its first one unless ``event`` is given).

    At the PD point (lambda*, P*) the fixed points of Phi_{2m} have a
    pitchfork: the m orbit's branch crosses the 2m branch, which leaves along
    the eigenvector e of the multiplier -1 at fixed lambda (P* +- eps e,
    eps ~ sqrt(lambda - lambda*)).  Newton on the 2m problem from P* + eps e
    would fall back onto the m orbit (M_2m - I is nearly singular there);
    instead one pseudo-arclength corrector step from (P*, lambda*) along
    (e, 0) -- on the hyperplane e . (P - P*) = h s_x, lambda free -- lands on
    the 2m branch, which is then traced in both directions from there
    (``h``: the scaled distance of that first step).  The new branch keeps
    the first one's lambda interval and steps.
    """
    if event is None:
        pds = branch.events_of("period_doubling")
        if not pds:
            raise ValueError("the branch has no period doubling to switch at")
        event = pds[0]
    if event.type != "period_doubling" or event.monodromy is None:
        raise ValueError(f"event must be a period_doubling of the branch, got {event.type}")
    st = branch.settings
    m2 = 2 * branch.m
    sx, sl = st["scales"]["state"], st["scales"]["lambda"]
    lo, hi = min(st["start"], st["stop"]), max(st["start"], st["stop"])
    pb = _Problem(branch.model, branch.friction, branch.parameter, m2, steps=st["steps_per_period"], scales=(sx, sl),
                  interval=(lo, hi), tol=st["tol"])
    tracer = Tracer(pb, _steps(st["h0"], st["h_max"], st["h_min"], max_points or st.get("max_points", MAX_POINTS), detect))
    w, vecs = np.linalg.eig(event.monodromy)
    e = np.real(vecs[:, int(np.argmin(np.abs(w + 1.0)))])
    t0 = np.array([e[0] / sx, e[1] / sx, 0.0])
    t0 /= np.linalg.norm(t0)
    star = np.array([event.state[0], event.state[1], event.lam])
    first = None
    for hh in (h, 0.3 * h, 3.0 * h, 0.1 * h):
        for sign in (1.0, -1.0):
            s = tracer.correct(star / pb.scale + sign * hh * t0, sign * t0)
            if s is None:
                continue
            half = flow_run(pb.model_at(s.lam), branch.friction, s.P, branch.m, pb.steps)
            if float(np.max(np.abs(half.residual))) > 1e-6 * sx:
                first = s
                break
        if first is not None:
            break
    if first is None:
        raise ForcedShootingError(f"no period-{m2} branch found at the period doubling at "
                                  f"{branch.parameter}={event.lam:.10g}")
    t1 = tracer.tangent(first, None)
    if float(t1 @ ((first.u - star) / pb.scale)) < 0.0:
        t1 = -t1  # away from the PD point
    trace = tracer.trace(first, t1)
    events = trace.events
    events.insert(0, BranchEvent("branch_point", event.lam, event.state.copy(), event.multipliers,
                                 {"from": f"period doubling of the m={branch.m} branch"}))
    return ForcedBranch(model=branch.model, friction=branch.friction, parameter=branch.parameter, m=m2,
                        points=[_point(pb, s) for s in trace.solutions], events=events, end=trace.end,
                        settings={**st, "born_at": event.lam})


# -- brute force ----------------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class StroboscopicSweep:
    """The stroboscopic X (and X') of the last ``keep`` forcing periods at each lambda of a sweep.

    Attributes
    ----------
    parameter:
        lambda: ``omega`` or ``fex``.
    values:
        Its values, in the order they were run (each starting from the
        state the previous one ended in).
    x:
        X at the forcing phase tau = 0 at the end of each of the last
        ``keep`` forcing periods, shape (len(values), keep); a row of NaN
        where the run failed.
    v:
        X' at the same instants, shape (len(values), keep).
    """

    parameter: str
    values: np.ndarray
    x: np.ndarray  # (len(values), keep)
    v: np.ndarray
    #: at each value, the energy residual of the kept window (``keep`` forcing periods from its first section,
    #: re-run by the package's solver); NaN where the run failed
    energy_residual: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def points(self) -> tuple[np.ndarray, np.ndarray]:
        """(lambda, X) pairs, flattened, for a scatter plot."""
        return np.repeat(self.values, self.x.shape[1]), self.x.ravel()

    def multiple(self, j: int, rtol: float = 1e-6) -> int:
        """The smallest m with P_k = P_{k-m} over the kept points at values[j] (0 if none up to keep / 2)."""
        x, v = self.x[j], self.v[j]
        scale = max(float(np.max(np.abs(x))), float(np.max(np.abs(v))), 1e-12)
        for m in range(1, len(x) // 2 + 1):
            if np.all(np.abs(x[m:] - x[:-m]) <= rtol * scale) and np.all(np.abs(v[m:] - v[:-m]) <= rtol * scale):
                return m
        return 0


#: the brute-force sweep's defaults: forcing periods run before, and kept after, at each value; RK4 steps per period
SWEEP_TRANSIENT, SWEEP_KEEP, SWEEP_STEPS = 300, 40, 256


def stroboscopic_estimate(model: BeltOscillator, parameter: str, values: Sequence[float], *,
                          transient_periods: int = SWEEP_TRANSIENT, keep: int = SWEEP_KEEP,
                          steps: int = SWEEP_STEPS) -> Estimate:
    """:func:`stroboscopic_sweep`'s tangent runs: ``transient_periods + keep`` forcing periods at each value,
    the longest period (the lowest omega) taken for all."""
    slowest = replace(model, omega=float(min(values))) if parameter == "omega" else model
    periods = float(len(values)) * (transient_periods + keep)
    return located_run(periods * steps, periods * slowest.forcing_period, "tangent_step", slowest.omega)


def stroboscopic_sweep(model: BeltOscillator, friction: FrictionLaw, parameter: str, values: Sequence[float], *,
                       transient_periods: int = SWEEP_TRANSIENT, keep: int = SWEEP_KEEP, x0: float = 0.0, v0: float = 0.0,
                       steps: int = SWEEP_STEPS) -> StroboscopicSweep:
    """Brute force: at each lambda in ``values`` (in the given order), run the forced system and keep its section.

    Each value starts from the state the previous one ended in (state
    continuation, so a sweep up follows the branch it is on until it ends).
    Integrated by ``frictionflow.core.tangent.run`` (RK4, located
    switches); a run that fails leaves NaN.

    Parameters
    ----------
    model, friction:
        A forced oscillator and its law.
    parameter:
        lambda: ``omega`` or ``fex``.
    values:
        Its values, run in the given order.
    transient_periods:
        Forcing periods run at each value before its section is kept.
    keep:
        Forcing periods whose section (X, X') is kept at each value.
    x0, v0:
        The state the first value starts from.
    steps:
        RK4 steps per forcing period.

    Returns
    -------
    StroboscopicSweep
        ``parameter``, ``values``, the kept sections ``x``, ``v`` (one row per value) and the
        ``energy_residual`` of each value's kept window.
    """

    _check_model(model)
    _check_law(friction)
    if parameter not in PARAMETERS:
        raise ValueError(f"parameter must be one of {PARAMETERS}, got {parameter!r}")
    values = np.asarray(values, dtype=float)
    keep = _check_int("keep", keep, 1, 10**6)
    transient_periods = FORCED_RANGES["transient_periods"].check(transient_periods)
    xs = np.full((len(values), keep), np.nan)
    vs = np.full((len(values), keep), np.nan)
    res = np.full(len(values), np.nan)
    x, v = float(x0), float(v0)
    for j, lam in enumerate(values):
        mdl = replace(model, **{parameter: float(lam)})
        p = kernel_params(mdl, friction)
        strobe = np.zeros((transient_periods + keep, 3))
        est = np.zeros((keep, 2))
        counts = np.zeros(tangent.N_COUNTS, dtype=np.int64)
        status, _, _ = tangent.run(x, v, float(mdl.zeta), float(mdl.vb), p, float(mdl.forcing_period), int(steps),
                                   transient_periods, keep, strobe, est, counts)
        if status != tangent.OK:
            x, v = float(x0), float(v0)
            continue
        xs[j] = strobe[transient_periods:, 0]
        vs[j] = strobe[transient_periods:, 1]
        res[j] = _window_residual(mdl, friction, (xs[j, 0], vs[j, 0]), keep)
        x, v = float(strobe[-1, 0]), float(strobe[-1, 1])
    return StroboscopicSweep(parameter, values, xs, vs, res)


def _window_residual(model: BeltOscillator, friction: FrictionLaw, state: tuple[float, float], keep: int) -> float:
    """The energy residual of ``keep`` forcing periods from ``state`` (a section at phase 0); NaN where the
    measuring solver cannot run that forcing (see :func:`_check_measurable`)."""
    if auto_solver(friction, model).forcing_problem(model.zeta, model.omega, model.fex):
        return math.nan
    traj = one_period(model, friction, state, keep * float(model.forcing_period))
    return float(measures_of(traj).power.energy_residual)
