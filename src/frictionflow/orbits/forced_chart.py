"""The forced oscillator in two parameters: monitors along forced branches, their extrema, and (Omega, F_ex) curves.

>>> from frictionflow import BeltOscillator, Coulomb
>>> from frictionflow.orbits.forced import continue_forced
>>> from frictionflow.orbits.forced_chart import forced_branch_extrema
>>> model = BeltOscillator(zeta=0.05, vb=10.0, fex=0.1, omega=0.8)   # always slipping: the linear oscillator
>>> branch = continue_forced(model, Coulomb(0.5, 1.0), "omega", 0.8, 1.2)
>>> (e,) = forced_branch_extrema(branch, "P_ex")                     # the input power peaks at Omega = 1
>>> e.kind, round(e.value, 6)
('max', 1.0)

**Monitors.**  Every per-orbit quantity of a forced branch point is a
monitor (``FORCED_MONITORS``): the power averages over one orbit period
(P_ex, P_dv, P_fin, P_df, R_c, R_f, P_belt, P_heat), TR_B, the amplitude and
the stick fraction.  :func:`forced_branch_extrema` finds where one turns along
a traced :class:`~.forced.ForcedBranch` (its discrete slope in lambda changes
sign where lambda runs one way) and refines the point by Brent's bounded
minimisation of the monitor itself: at each trial lambda the orbit is solved
anew by Newton shooting (from the branch's states interpolated there) and
measured by the same flow-map run that gives its monodromy.  A monitor with a
corner (at a grazing, where a stick phase appears) is refined as well: Brent
needs no slope.

:func:`continue_forced_extremum` follows one extremum as a second parameter
varies (the issue's example: the forcing frequency of least or greatest
TR_B as F_ex varies): at each new value the orbit is re-solved at the last
extremum and the extremum refined in a window around it.

**Curves in two parameters.**  :func:`forced_chart` continues the m-period
orbits in ``x_param`` (Omega or F_ex) at each value of a grid of
``y_param`` and collects the special points each continuation refines to
~1e-8 in x: folds, period doublings, Neimark-Sacker points and grazings.
Each is a point (x, y) of a codimension-one curve, exact in y (the grid
value) and located to ~1e-8 in x; points of one kind and m at neighbouring
grid values are joined into curves.  Each grid value starts from the orbit
of the previous one (Newton from its state), so the chart follows one
family of orbits through the plane: each m is a curve source of the chart
engine (:mod:`.charting`), traced over the y grid.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from .._display import Row, num
from .._lazy import lazy_module
from ..estimate import Estimate, enforce
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .charting import Chart, Codim2, Curve, CurvePoint, HeatMap, dedupe, trace
from .extrema import FORCED_MONITORS, Extremum
from .forced import (
    PARAMETERS,
    ForcedBranch,
    branch_estimate,
    branch_steps,
    ForcedShootingError,
    continue_forced,
    find_forced_orbit,
    measures,
    newton,
)
from .settings import ForcedContinuationSettings, merged

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick
#: the special points of forced branches that make curves in two parameters
FORCED_CURVES = ("fold", "period_doubling", "neimark_sacker", "grazing")


def _check_monitor(monitor: str) -> str:
    if monitor not in FORCED_MONITORS:
        raise ValueError(f"monitor must be one of {', '.join(FORCED_MONITORS)}, got {monitor!r}")
    return monitor


def forced_monitor_value(point: Any, monitor: str) -> float:
    """The monitor's value at a forced branch point, a :class:`~.forced.ForcedOrbit` or a :func:`~.forced.measures` dict."""
    _check_monitor(monitor)
    get = point.get if isinstance(point, dict) else (lambda k: getattr(point, k))
    if monitor in ("TR_B", "amplitude", "stick_fraction"):
        return float(get(monitor))
    return float(get("averages")[monitor])


def forced_monitor(branch: ForcedBranch, monitor: str) -> np.ndarray:
    """The monitor at every point of the branch."""
    return np.array([forced_monitor_value(p, monitor) for p in branch.points])


# -- the monitor as a function of lambda -----------------------------------------------------------------------------
class _OrbitFunction:
    """The monitor of the m-period orbit as a function of lambda, each orbit solved by Newton shooting.

    ``guess(lam)`` gives Newton's start (the branch's states interpolated, or
    the last solved orbit); the last solved state is kept for the next call.
    """

    def __init__(self, model: BeltOscillator, law: FrictionLaw, parameter: str, m: int, steps: int, monitor: str,
                 guess, tol: float = 1e-12) -> None:
        self.model, self.law, self.parameter, self.m, self.steps = model, law, parameter, m, steps
        self.monitor, self.guess, self.tol = monitor, guess, tol
        self.last: np.ndarray | None = None

    def solve(self, lam: float):
        mdl = replace(self.model, **{self.parameter: float(lam)})
        tries = [self.guess(lam)] + ([self.last] if self.last is not None else [])
        err: Exception | None = None
        for P in tries:
            for tol in (self.tol, 1e-10):  # rounding may floor the residual above the tight tolerance
                try:
                    run, _ = newton(mdl, self.law, P, self.m, self.steps, tol, 30)
                    self.last = run.start.copy()
                    return mdl, run
                except (RuntimeError, ValueError) as e:
                    err = e
        raise ForcedShootingError(f"no {self.m}-period orbit at {self.parameter}={lam:.12g}: {err}")

    def value(self, lam: float) -> tuple[float, np.ndarray]:
        """(monitor, state at tau = 0) of the orbit at lambda."""
        mdl, run = self.solve(lam)
        return forced_monitor_value(measures(mdl, self.law, run), self.monitor), run.start.copy()


def _brent(f: _OrbitFunction, lo: float, hi: float, kind: str) -> tuple[float, float, np.ndarray]:
    """Brent's bounded minimisation of -+monitor on [lo, hi]: (lambda, monitor, state)."""
    sign = -1.0 if kind == "max" else 1.0
    res = optimize.minimize_scalar(lambda v: sign * f.value(v)[0], bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-10 * max(abs(lo), abs(hi), 1e-12)})
    lam = float(res.x)
    value, state = f.value(lam)
    return lam, value, state


def refine_forced_extremum(model: BeltOscillator, law: FrictionLaw, parameter: str, monitor: str, lo: float, hi: float,
                           guess: Sequence[float] | Any, kind: str, *, m: int = 1, steps: int = 512) -> Extremum:
    """The extremum (``kind`` max or min) of ``monitor`` for lambda in [lo, hi] on the m-period orbit near ``guess``.

    ``guess``: a state (X, X') at tau = 0 near the orbits of the interval, or a
    callable lambda -> state.
    """
    _check_monitor(monitor)
    if kind not in ("max", "min"):
        raise ValueError(f"kind must be max or min, got {kind!r}")
    g = guess if callable(guess) else (lambda lam, P=np.asarray(guess, dtype=float): P)
    f = _OrbitFunction(model, law, parameter, m, steps, monitor, g)
    lam, value, state = _brent(f, lo, hi, kind)
    return Extremum(monitor, kind, parameter, lam, value, float(state[0]), method="brent",
                    extra={"V": float(state[1]), "m": m})


def _stretches(lam: np.ndarray, mon: np.ndarray, noise: float = 1e-9):
    """(i, kind) of interior discrete extrema of the monitor where lambda runs one way across them.

    Turns by less than ``noise`` of the monitor's size on the branch are
    rounding (a monitor constant along the branch, as P_belt = F_d V_b in
    pure slip), not extrema.
    """
    finite = mon[np.isfinite(mon)]
    floor = noise * (float(np.max(np.abs(finite))) if len(finite) else 0.0)
    for i in range(1, len(lam) - 1):
        if not np.all(np.isfinite(mon[i - 1:i + 2])):
            continue
        if min(abs(mon[i] - mon[i - 1]), abs(mon[i + 1] - mon[i])) <= floor:
            continue
        if (lam[i] - lam[i - 1]) * (lam[i + 1] - lam[i]) <= 0:
            continue  # a fold between: an extremum in arclength, not in lambda
        s1 = (mon[i] - mon[i - 1]) / (lam[i] - lam[i - 1])
        s2 = (mon[i + 1] - mon[i]) / (lam[i + 1] - lam[i])
        if s1 * s2 < 0:
            below = s1 if lam[i] > lam[i - 1] else s2
            yield i, ("max" if below > 0 else "min")


def _interpolator(branch: ForcedBranch, i: int):
    """lambda -> the state interpolated linearly between the branch points i - 1, i, i + 1 (lambda monotone there)."""
    pts = branch.points[i - 1:i + 2]
    lam = np.array([p.lam for p in pts])
    order = np.argsort(lam)
    lam = lam[order]
    xs = np.array([pts[k].state[0] for k in order])
    vs = np.array([pts[k].state[1] for k in order])
    return lambda v: np.array([np.interp(v, lam, xs), np.interp(v, lam, vs)])


def forced_branch_extrema(branch: ForcedBranch, monitor: str, *, refine: bool = True) -> list[Extremum]:
    """Extrema of ``monitor`` along a forced branch, refined by Brent on the re-shot orbits unless ``refine`` is False.

    Each :class:`~frictionflow.orbits.Extremum` carries lambda (``value``), the monitor
    there, X (``x``) and, in ``extra``, X' (``V``), m and ``at``: ``grazing
    corner`` where the stick-phase count changes across the extremum.

    Parameters
    ----------
    branch:
        A branch from :func:`~frictionflow.orbits.continue_forced`.
    monitor:
        The quantity (``P_fin``, ``P_ex``, ``R_c``, ``TR_B``, ``amplitude``, ...; see ``FORCED_MONITORS``).
    refine:
        Refine each extremum on re-shot orbits (False: the best branch point).
    """
    _check_monitor(monitor)
    lam = branch.lam
    mon = forced_monitor(branch, monitor)
    steps = int(branch.settings.get("steps_per_period", 512))
    out = []
    for i, kind in _stretches(lam, mon):
        pts = branch.points
        corner = {"at": "grazing corner"} if len({p.stick_phases for p in pts[i - 1:i + 2]}) > 1 else {}
        if not refine:
            out.append(Extremum(monitor, kind, branch.parameter, float(lam[i]), float(mon[i]), float(pts[i].state[0]),
                                None, "sample", {"V": float(pts[i].state[1]), "m": branch.m, **corner}))
            continue
        lo, hi = sorted((float(lam[i - 1]), float(lam[i + 1])))
        try:
            e = refine_forced_extremum(branch.model, branch.friction, branch.parameter, monitor, lo, hi,
                                       _interpolator(branch, i), kind, m=branch.m, steps=steps)
            out.append(Extremum(e.monitor, e.kind, e.param, e.value, e.monitor_value, e.x, None, e.method,
                                {**e.extra, **corner}))
        except (RuntimeError, ValueError):
            out.append(Extremum(monitor, kind, branch.parameter, float(lam[i]), float(mon[i]), float(pts[i].state[0]),
                                None, "sample", {"V": float(pts[i].state[1]), "m": branch.m, **corner}))
    return out


def continue_forced_extremum(model: BeltOscillator, law: FrictionLaw, monitor: str, parameter: str, lo: float,
                             hi: float, param2: str, values2, start: Extremum, *, m: int = 1, steps: int = 512,
                             width: float = 0.05) -> list[Extremum]:
    """Follow the extremum ``start`` of ``monitor`` along ``parameter`` through ``values2`` of ``param2``.

    ``start`` was found at ``model``'s value of ``param2`` (e.g. by
    :func:`forced_branch_extrema`).  At each value the orbit is re-solved
    from the last extremum's state and the extremum refined in a window of
    ``width`` of [lo, hi] around the last one (widened twice while it lands
    on the window's edge).  Stops at the first value where it is lost.  Each
    result names ``param2``'s value in ``extra``.

    Parameters
    ----------
    model, law:
        The forced oscillator and its law at ``start``.
    monitor:
        The quantity whose extremum is followed.
    parameter:
        The branch's parameter, lambda (``omega`` or ``fex``).
    lo, hi:
        The interval of lambda searched.
    param2, values2:
        The second parameter and its values, in the order followed.
    start:
        The extremum at ``model``'s value of ``param2``.
    m:
        The orbits' period in forcing periods.
    steps:
        RK4 steps per forcing period.
    width:
        The search window around the last extremum, as a fraction of [lo, hi].
    """

    _check_monitor(monitor)
    for name in (parameter, param2):
        if name not in PARAMETERS:
            raise ValueError(f"parameters must be among {PARAMETERS}, got {name!r}")
    if parameter == param2:
        raise ValueError("the two parameters must differ")
    lam, state = start.value, np.array([start.x, start.extra.get("V", model.vb)])
    span = hi - lo
    out = []
    for v2 in values2:
        m2 = replace(model, **{param2: float(v2)})
        found = None
        for w in (width, 2 * width, 4 * width):
            a, b = max(lo, lam - w * span), min(hi, lam + w * span)
            try:
                e = refine_forced_extremum(m2, law, parameter, monitor, a, b, state, start.kind, m=m, steps=steps)
            except (RuntimeError, ValueError):
                continue
            edge = min(e.value - a, b - e.value)
            if edge > 1e-6 * (b - a):
                found = e
                break
        if found is None:
            break
        lam, state = found.value, np.array([found.x, found.extra["V"]])
        out.append(Extremum(found.monitor, found.kind, parameter, found.value, found.monitor_value, found.x, None,
                            found.method, {**found.extra, param2: float(v2)}))
    return out


# -- curves in two parameters ------------------------------------------------------------------------------------
@dataclass
class GridRun:
    """What the continuation at one grid value of y did: its points, how it ended, the events it found."""

    y: float
    m: int
    points: int
    ends: list[str]
    events: list[str]
    error: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"y": self.y, "m": self.m, "points": self.points, "ends": self.ends, "events": self.events,
                "error": self.error or None}


@dataclass(repr=False, eq=False)
class ForcedChart(Chart):
    """Curves of forced special points in the (x, y) plane (continued in x at each y of a grid), and a heat map.

    The curves' points are (x, y) with y a grid value; ``grid_axis`` is "y".

    Its fields, shared by every chart, are listed below.
    """

    grid_axis: str = "y"

    @property
    def x_range(self) -> tuple[float, float]:
        return self.span

    @property
    def y_values(self) -> np.ndarray:
        return self.grid

    def _notes(self) -> list[Row]:
        failed = [r for r in self.runs if r.error]
        return [("no orbit at", ", ".join(f"{self.y_param}={num(r.y)} (m={r.m})" for r in failed))] if failed else []


def _start_orbit(model: BeltOscillator, law: FrictionLaw, m: int, previous: np.ndarray | None, steps: int):
    """The m-period orbit at ``model``: Newton from the previous grid value's orbit, else after a transient."""
    if previous is not None:
        try:
            return find_forced_orbit(model, law, m, float(previous[0]), float(previous[1]), steps=steps)
        except (RuntimeError, ValueError):
            pass
    return find_forced_orbit(model, law, m, steps=steps)


def _event_point(e, y: float, m: int) -> CurvePoint:
    detail = {"m": m, "X": float(e.state[0]), "V": float(e.state[1]),
              "multipliers": [[float(z.real), float(z.imag)] for z in e.multipliers]}
    for k in ("smooth", "angle", "stick_phase", "slip_reversal", "at"):
        if k in e.detail:
            detail[k] = e.detail[k]
    return CurvePoint(float(e.lam), float(y), detail)


@dataclass
class _ForcedOrbits:
    """The m-period orbits continued in x from ``x_start`` to both ends of ``x_range`` at each grid value of y.

    Each grid value starts from the previous one's orbit (``previous``), so
    one family is followed through the plane; each continuation is recorded in ``runs``.
    """

    model: BeltOscillator
    law: FrictionLaw
    x_param: str
    y_param: str
    x_range: tuple[float, float]
    x_start: float
    m: int
    kinds: Sequence[str]
    continuation: ForcedContinuationSettings
    previous: np.ndarray | None = None
    runs: list[GridRun] = field(default_factory=list)

    def at(self, index: int, y: float) -> list[tuple[str, CurvePoint]]:
        mdl = replace(self.model, **{self.y_param: y, self.x_param: self.x_start})
        try:
            orbit = _start_orbit(mdl, self.law, self.m, self.previous, int(self.continuation.steps))
        except (RuntimeError, ValueError) as e:
            self.runs.append(GridRun(y, self.m, 0, [], [], str(e)))
            self.previous = None  # lost: the next value starts afresh
            return []
        self.previous = orbit.state
        ends, names, n, out = [], [], 0, []
        for stop in self.x_range:
            if stop == self.x_start:
                continue
            try:
                br = continue_forced(mdl, self.law, self.x_param, self.x_start, stop, m=self.m, orbit=orbit,
                                     settings=self.continuation)
            except (RuntimeError, ValueError) as e:
                ends.append(f"failed: {e}")
                continue
            n += len(br)
            ends.append(br.end)
            names += [e.type for e in br.events]
            out += [(e.type, _event_point(e, y, self.m)) for e in br.events if e.type in self.kinds]
        self.runs.append(GridRun(y, self.m, n, ends, names))
        return out

    def curves(self, found: dict[str, list[CurvePoint]]) -> tuple[list[Curve], list[Codim2]]:
        tol = 1e-7 * (self.x_range[1] - self.x_range[0])  # the continuations both ways meet the start's event
        return [Curve(kind, dedupe(pts, tol, "y"), m=self.m) for kind, pts in sorted(found.items())], []


def _check_plane(x_param: str, x_range, y_param: str, y_values, curves: Sequence[str]) -> tuple[tuple[float, float], np.ndarray]:
    """((lo, hi) of x, the y grid) of a valid forced plane; ValueError naming what is wrong."""
    for name in (x_param, y_param):
        if name not in PARAMETERS:
            raise ValueError(f"parameters must be among {PARAMETERS}, got {name!r}")
    if x_param == y_param:
        raise ValueError("the two parameters must differ")
    for c in curves:
        if c not in FORCED_CURVES:
            raise ValueError(f"curves must be among {', '.join(FORCED_CURVES)}, got {c!r}")
    lo, hi = sorted(float(v) for v in x_range)
    if not (lo > 0 and hi > lo):
        raise ValueError(f"{x_param}: the range must be positive with two distinct ends, got {x_range!r}")
    ys = np.asarray(y_values, dtype=float)
    if not (ys.ndim == 1 and len(ys) >= 1 and np.all(ys > 0) and np.all(np.isfinite(ys))):
        raise ValueError(f"{y_param}: the grid values must be finite and > 0")
    return (lo, hi), ys


def forced_chart(
    model: BeltOscillator,
    law: FrictionLaw,
    x_param: str,
    x_range: tuple[float, float],
    y_param: str,
    y_values,
    *,
    m: int | Sequence[int] = 1,
    x_start: float | None = None,
    guess: Sequence[float] | None = None,
    curves: Sequence[str] = FORCED_CURVES,
    continuation: ForcedContinuationSettings | None = None,
    **options: Any,
) -> ForcedChart:
    """Fold, period-doubling, Neimark-Sacker and grazing curves of the forced system in the (x_param, y_param) plane.

    At each y of ``y_values`` the m-period orbit (for each m given) is found
    at x = ``x_start`` (default: the end of ``x_range`` nearer ``model``'s x)
    and continued by :func:`~frictionflow.orbits.continue_forced` in x to both ends of
    ``x_range``; the special points it refines are the curves' points.

    Parameters
    ----------
    model, law:
        The forced oscillator and its friction law (with Coulomb's stick rule), at the other parameters' values.
    x_param, x_range:
        The parameter continued (``omega`` or ``fex``) and its interval.
    y_param, y_values:
        The other one and its grid values.
    m:
        The orbits' period(s) in forcing periods: one curve source per m.
    x_start:
        Where each continuation starts (clipped to ``x_range``).
    guess:
        (X, X') at tau = 0 near the first grid value's orbit (else a
        transient is run first); later grid values start from the previous one's orbit.
    curves:
        The kinds of curve wanted (among ``fold``, ``period_doubling``,
        ``neimark_sacker``, ``grazing``).
    continuation:
        How each branch is traced (:class:`~.settings.ForcedContinuationSettings`).
    **options:
        ``sweep``, ``heat``: an xarray dataset of simulations on the same
        plane and its variable drawn under the curves (as :func:`forced_map`
        makes them); and any field of :class:`~.settings.ForcedContinuationSettings`
        (``steps``, ``h0``, ``h_max``, ``h_min``, ``max_points``, ``detect``,
        ``tol``), replacing the one of ``continuation``.  A TypeError names
        any other keyword.
    """
    sweep, heat = options.pop("sweep", None), options.pop("heat", "TR_B")
    settings = merged(ForcedContinuationSettings, continuation, options, "forced_chart", "continuation")
    (lo, hi), ys = _check_plane(x_param, x_range, y_param, y_values, curves)
    settings = chart_settings(model, (x_param, (lo, hi)), (y_param, ys), settings)
    ms = (m,) if isinstance(m, (int, np.integer)) else tuple(m)
    enforce(forced_chart_estimate(model, (x_param, (lo, hi)), (y_param, ys), ms, settings))  # within the limits in force
    if x_start is None:
        here = float(getattr(model, x_param))
        x_start = lo if abs(here - lo) <= abs(here - hi) else hi
    x_start = float(min(max(x_start, lo), hi))
    start = None if guess is None else np.asarray(guess, dtype=float)
    sources = [_ForcedOrbits(model, law, x_param, y_param, (lo, hi), x_start, mm, curves, settings, start)
               for mm in ms]
    out_curves, _ = trace(sources, ys)
    return ForcedChart(x_param, y_param, ys, (lo, hi), {**model.report(), **law.as_dict(), "m": list(ms)},
                       sorted(out_curves, key=lambda c: (c.kind, c.m)), runs=[r for s in sources for r in s.runs],
                       sweep=sweep, heat=heat if sweep is not None else "", continued_in=x_param)


def chart_settings(model: BeltOscillator, x: tuple[str, tuple[float, float]], y: tuple[str, Sequence[float]],
                   settings: ForcedContinuationSettings) -> ForcedContinuationSettings:
    """``settings`` with one RK4 grid for the whole chart: the given steps, else the default that fits the
    slowest forcing on the plane (every branch and start orbit then shares it)."""
    (x_param, x_range), (y_param, ys) = x, y
    slowest = min(x_range) if x_param == "omega" else (float(np.min(ys)) if y_param == "omega" else model.omega)
    return replace(settings, steps=branch_steps(model, "omega", (slowest, slowest), settings.steps))


def forced_chart_estimate(model: BeltOscillator, x: tuple[str, tuple[float, float]], y: tuple[str, Sequence[float]],
                          ms: Sequence[int], settings: ForcedContinuationSettings) -> Estimate:
    """A branch over the x interval (``x``: its name and ends) at each y value (``y``: its name and values) and
    each m of ``ms``, as :func:`~.forced.branch_estimate` estimates one."""
    settings = chart_settings(model, x, y, settings)
    (x_param, x_range), (y_param, ys) = x, y
    runs = [branch_estimate(replace(model, **{y_param: float(v)}), x_param, x_range, mm, settings, True)
            for v in ys for mm in ms]
    return Estimate(float(len(runs)), "branches", sum(r.seconds for r in runs))


def forced_map(model: BeltOscillator, law: FrictionLaw, x_param: str, x_range, y_param: str, y_values, *,
               sweep_shape: tuple[int, int] | None = None, sweep_out: Any = None, t_end: float = 500.0,
               heat: str = "TR_B", sweep_y_range: tuple[float, float] | None = None, **kw: Any) -> ForcedChart:
    """:func:`forced_chart` with a heat map from a sweep of simulations over the same plane.

    Parameters
    ----------
    model, law, x_param, x_range, y_param, y_values:
        The system and the plane, as :func:`forced_chart`.
    sweep_shape:
        (n_x, n_y), the sweep's grid (None: no sweep), run by
        :func:`frictionflow.sweep.run_sweep` (keep it coarse).
    sweep_out:
        Where the sweep is written (.zarr or .nc; default a temporary .nc).
    t_end:
        Length of each simulation of the sweep.
    heat:
        The sweep variable drawn under the curves (TR_B, R_c, ...).
    sweep_y_range:
        The sweep's y interval (default: the grid's).
    **kw:
        Passed on to :func:`forced_chart`.
    """

    ys = np.asarray(y_values, dtype=float)
    y_sweep = sweep_y_range if sweep_y_range is not None else (float(ys.min()), float(ys.max()))
    heat_map = HeatMap(sweep_shape, sweep_out, t_end, heat)
    m = kw.get("m", 1)
    settings = replace(kw.get("continuation") or ForcedContinuationSettings(),
                       **{k: kw[k] for k in ("steps", "max_points") if k in kw})
    curves = forced_chart_estimate(model, (x_param, (min(x_range), max(x_range))), (y_param, ys),
                                   (m,) if isinstance(m, (int, np.integer)) else tuple(m), settings)
    sweep_cost = heat_map.estimate(model, law, x_param, x_range, y_param, y_sweep)
    enforce(curves if sweep_cost is None else curves.then(sweep_cost))  # within the limits in force, if any
    sweep = heat_map.run(model, law, x_param, x_range, y_param, y_sweep)
    return forced_chart(model, law, x_param, x_range, y_param, y_values, sweep=sweep, heat=heat, **kw)
