"""Monitors along branches: any per-orbit quantity, its extrema located, and an extremum followed in a second parameter.

A *monitor* is one number per orbit of a branch: the averages P_fin, P_dv,
P_df, R_c, R_f, P_belt, P_heat, TR_B, the amplitude, the stick fraction or
the period (``MONITORS``).  :func:`branch_extrema` finds where a monitor
is extreme along a traced branch (a sign change of its discrete slope where
the parameter runs one way) and refines the point:

* monitors with an exact slope on the compiled engine (P_dv, P_fin, P_df,
  R_c, R_f, amplitude, period: :mod:`.sensitivity`) by a root of that slope,
  to rounding in lambda;
* the others (TR_B, stick fraction, P_belt, P_heat, or any monitor on the
  closed-form engine) by Brent's minimisation of the monitor itself
  (orbits solved at each lambda, their measures integrated by the package's
  solver), to ~1e-9 of the interval in lambda.

:func:`continue_extremum` follows one extremum as a second parameter varies:
at each new value the orbit is solved near the last extremum and the
extremum refined again locally (a natural-parameter continuation of the
codimension-one condition dM/dlambda = 0).

Forced branches (:class:`~.forced.ForcedBranch`) are monitored the same way
-- :func:`monitor_value` and :func:`branch_extrema` take their points and
branches too, with P_ex among the monitors (``FORCED_MONITORS``); the
work is done by :mod:`.forced_chart` (Brent on re-shot orbits), where
:func:`~.forced_chart.continue_forced_extremum` follows a forced extremum in
the second forcing parameter.
"""

from __future__ import annotations

import math

import numpy as np

from .._lazy import lazy_module
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .branches import Branch, BranchPoint, ContinuationResult
from .cycle_problem import CycleProblem
from .extrema import FORCED_MONITORS, MONITORS, Extremum  # noqa: F401  (FORCED_MONITORS: re-exported)
from .forced import BranchPoint as ForcedPoint, ForcedBranch
from .forced_chart import forced_branch_extrema, forced_monitor_value
from .parameters import get_param, with_param
from .sensitivity import EXACT_MONITORS, orbit_derivatives
from .shooting import orbit_from_segment

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick

def monitor_value(point: BranchPoint, monitor: str) -> float:
    """The monitor's value at a branch point (NaN where undefined, as R_c at an equilibrium); forced points too."""
    if isinstance(point, ForcedPoint):
        return forced_monitor_value(point, monitor)
    if monitor not in MONITORS:
        raise ValueError(f"monitor must be one of {', '.join(MONITORS)}, got {monitor!r}")
    if monitor == "amplitude":
        return float(point.amplitude)
    if monitor == "stick_fraction":
        return float(point.stick_fraction)
    if monitor == "period":
        return math.nan if point.period is None else float(point.period)
    if monitor == "TR_B":
        return float(point.measures.TR_B)
    return float(getattr(point.measures.power, monitor))


class _BranchFunction:
    """The monitor (and its slope) as a function of lambda along one stretch of a branch."""

    def __init__(self, model: BeltOscillator, law: FrictionLaw, param: str, lo: float, hi: float, monitor: str, returns: int = 1) -> None:
        self.problem = CycleProblem(model, law, param, lo, hi, returns=returns)
        self.monitor, self.param, self.returns = monitor, param, returns
        self.exact = monitor in EXACT_MONITORS and self.problem.locatable and not law.piecewise_constant
        self.xi = math.nan  # the last solved orbit, the next guess

    def orbit(self, lam: float):
        s = self.problem.solve_at(lam, self.xi)
        self.xi = s.xi
        return s

    def slope(self, lam: float) -> float:
        s = self.orbit(lam)
        return orbit_derivatives(s.model, s.law, self.param, s.x, self.returns).slopes[self.monitor]

    def value(self, lam: float) -> tuple[float, float]:
        """(monitor, X) of the orbit at lambda, measured as branch points are."""
        s = self.orbit(lam)
        if self.exact:
            return orbit_derivatives(s.model, s.law, self.param, s.x, self.returns).values[self.monitor], s.x
        orbit = orbit_from_segment(s.model, s.law, s.seg, residual=s.G, iterations=s.iterations, returns=self.returns)
        return monitor_value(BranchPoint.from_orbit(lam, orbit), self.monitor), s.x


def refine_extremum(model: BeltOscillator, law: FrictionLaw, param: str, monitor: str, lo: float, hi: float, x_guess: float,
                    kind: str, *, returns: int = 1) -> Extremum:
    """The extremum (``kind`` max or min) of ``monitor`` for lambda in [lo, hi] on the branch through x_guess."""
    f = _BranchFunction(model, law, param, lo, hi, monitor, returns)
    _, _, x_ref = f.problem.system(0.5 * (lo + hi))
    f.xi = x_guess - (x_ref if math.isfinite(x_ref) else 0.0)
    sign = -1.0 if kind == "max" else 1.0
    lam = math.nan
    if f.exact:
        try:
            sa, sb = f.slope(lo), f.slope(hi)
            if sa * sb < 0:
                lam = optimize.brentq(f.slope, lo, hi, xtol=1e-14 * max(abs(lo), abs(hi), 1e-12), rtol=4 * np.finfo(float).eps)
                method = "slope root"
        except (RuntimeError, ValueError):
            lam = math.nan
    if not math.isfinite(lam):
        f.xi = x_guess - (x_ref if math.isfinite(x_ref) else 0.0)
        res = optimize.minimize_scalar(lambda v: sign * f.value(v)[0], bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-10 * max(hi - lo, 1e-12)})
        lam = float(res.x)
        method = "brent"
    m, x = f.value(lam)
    return Extremum(monitor, kind, param, float(lam), float(m), float(x), method=method)


def _stretches(branch: Branch, monitor: str):
    """(i, kind) of interior discrete extrema of the monitor where the parameter runs one way across them."""
    v = np.array(branch.values())
    m = np.array([monitor_value(p, monitor) for p in branch.points])
    for i in range(1, len(v) - 1):
        if not np.all(np.isfinite(m[i - 1:i + 2])):
            continue
        if (v[i] - v[i - 1]) * (v[i + 1] - v[i]) <= 0:
            continue  # a fold between: an extremum in arclength, not in the parameter
        # the slope's sign in lambda changes: the monitor turns (rising below it: a maximum)
        s1 = (m[i] - m[i - 1]) / (v[i] - v[i - 1])
        s2 = (m[i + 1] - m[i]) / (v[i + 1] - v[i])
        if s1 * s2 < 0:
            below = s1 if v[i] > v[i - 1] else s2
            yield i, ("max" if below > 0 else "min")


def _at_grazing(model, law, param, monitor, lam, pts, i, kind, returns) -> Extremum:
    """The monitor on the grazing corner at ``lam`` (the orbit solved from the slip-only neighbour)."""
    slip = next(p for p in (pts[i - 1], pts[i], pts[i + 1]) if p.stick_fraction == 0)
    f = _BranchFunction(model, law, param, min(lam, slip.value), max(lam, slip.value) + 1e-300, monitor, returns)
    _, _, x_ref = f.problem.system(lam)
    f.xi = slip.x - (x_ref if math.isfinite(x_ref) else 0.0)
    m, x = f.value(lam)
    return Extremum(monitor, kind, param, float(lam), float(m), float(x), method="grazing")


def branch_extrema(result, monitor: str, model: BeltOscillator | None = None, law: FrictionLaw | None = None, *,
                   refine: bool = True, returns: int = 1) -> list[Extremum]:
    """Extrema of ``monitor`` along every periodic branch of ``result`` (refined unless ``refine`` is False).

    Parameters
    ----------
    result:
        A :class:`ContinuationResult`, or a forced branch
        (:class:`~.forced.ForcedBranch`, which carries its system:
        :func:`~frictionflow.orbits.forced_branch_extrema`).
    monitor:
        The quantity (``P_fin``, ``P_dv``, ``R_c``, ``TR_B``, ``amplitude``, ...; see ``MONITORS``).
    model, law:
        The system the continuation ran on (its other parameters).
    refine:
        Refine each extremum as a root of its exact slope (False, and always for a law with internal state:
        the best branch point).
    returns:
        Section crossings per period, as in the continuation.
    """
    if isinstance(result, ForcedBranch):
        return forced_branch_extrema(result, monitor, refine=refine)
    if model is None or law is None:
        raise ValueError("model and law: give the system the continuation ran on")
    refine = refine and law.stick_rule != "state"  # the exact slopes are the section map's: internal states have none
    out = []
    for index, branch in enumerate(result.branches):
        if branch.kind != "periodic":
            continue
        pts = branch.points
        for i, kind in _stretches(branch, monitor):
            a, b = sorted((pts[i - 1].value, pts[i + 1].value))
            if not refine:
                out.append(Extremum(monitor, kind, result.param, pts[i].value, monitor_value(pts[i], monitor), pts[i].x, index, "sample"))
                continue
            # across a grazing the branch has a corner: the extremum may sit on it (found by Brent, not a slope root)
            corner = {"at": "grazing corner"} if (pts[i - 1].stick_fraction > 0) != (pts[i + 1].stick_fraction > 0) else {}
            try:
                graze = [g.value for g in result.bifurcations if g.type == "grazing" and g.branch == index and a <= g.value <= b]
                if corner and graze:
                    e = _at_grazing(model, law, result.param, monitor, graze[0], pts, i, kind, returns)
                else:
                    e = refine_extremum(model, law, result.param, monitor, a, b, pts[i].x, kind, returns=returns)
            except (RuntimeError, ValueError):
                e = Extremum(monitor, kind, result.param, pts[i].value, monitor_value(pts[i], monitor), pts[i].x, index, "sample")
            out.append(Extremum(e.monitor, e.kind, e.param, e.value, e.monitor_value, e.x, index, e.method, corner))
    return out


def continue_extremum(model: BeltOscillator, law: FrictionLaw, monitor: str, param: str, lo: float, hi: float,
                      param2: str, values2, start: Extremum, *, width: float = 0.05, returns: int = 1) -> list[Extremum]:
    """Follow the extremum ``start`` (found at the current value of ``param2``) through ``values2`` of ``param2``.

    At each value the orbit is solved at the last extremum's lambda and X, and
    the extremum refined in a window of ``width`` of [lo, hi] around it (widened
    while the slope does not change sign there).  Stops at the first value
    where the extremum is lost.

    Parameters
    ----------
    model, law:
        The oscillator and its law at ``start``.
    monitor:
        The quantity whose extremum is followed.
    param:
        The branch's parameter, lambda.
    lo, hi:
        The interval of lambda searched.
    param2, values2:
        The second parameter and its values, in the order followed.
    start:
        The extremum at the current value of ``param2`` (from :func:`branch_extrema`).
    width:
        The search window around the last extremum, as a fraction of [lo, hi].
    returns:
        Section crossings per period.
    """

    out = []
    lam, x = start.value, start.x
    span = hi - lo
    for v2 in values2:
        m2, l2 = with_param(model, law, param2, float(v2))
        found = None
        for w in (width, 2 * width, 4 * width):
            a, b = max(lo, lam - w * span), min(hi, lam + w * span)
            try:
                e = refine_extremum(m2, l2, param, monitor, a, b, x, start.kind, returns=returns)
            except (RuntimeError, ValueError):
                continue
            if a < e.value < b and not (min(abs(e.value - a), abs(e.value - b)) < 1e-6 * span):
                found = e
                break
        if found is None:
            break
        lam, x = found.value, found.x
        out.append(Extremum(found.monitor, found.kind, param, found.value, found.monitor_value, found.x, None, found.method,
                            {param2: float(v2)}))
    return out

