"""Stability charts in two parameters: Hopf, grazing and fold curves, and their codimension-two points.

For a grid of the first parameter (``x``), the curves are the values of the
second (``y``) where a codimension-one condition holds, each found by a
sign change on a scan of ``y`` and refined to rounding:

* **hopf**: the sliding equilibrium loses stability, trace A = -(2 zeta + F'(V_b)) = 0
  (brentq).  Its criticality comes from the first Lyapunov coefficient of
  u'' + u = F(V_b - u') - F(V_b) - 2 zeta u', which is l1 = -F'''(V_b) / 16
  (the normal form of x' = -y + f(x), y' = x has 16 l1 = f'''; here
  f(w) = F(V_b - w) - ..., so f''' = -F'''): supercritical where F'''(V_b) > 0.
  A sign change of l1 along the curve is a **Bautin** (generalised Hopf)
  point, refined by brentq along the curve.
* **grazing**: the stick-slip cycle's first slip excursion touches V_r = 0
  (:func:`~.sensitivity.stick_slip_margin` changes sign; refined by
  Newton with the exact slope).  On one side a stick-slip cycle exists, on
  the other the slip excursion never returns to the belt speed.  For laws with
  F(0+) = F_s (Stribeck, cubic) this is also where a slip-only cycle touches
  the belt speed.
* **fold**: folds of cycles found by one-parameter continuation in ``y`` at
  each ``x`` and located by Newton (:func:`~.sensitivity.locate_fold`);
  non-smooth folds at a grazing corner are kept apart (``fold_at_grazing``).
  Where a smooth fold curve ends on the grazing curve (between two ``x``
  where the fold is smooth on one side and gone or at the grazing on the
  other) the **fold-grazing** point is reported at the grid resolution
  (``located: false``).

The curves are point-wise one-parameter locations on the ``x`` grid (a
curve that turns back in ``x`` shows as two values of ``y`` at one ``x``).
Each kind is a curve source of the chart engine (:mod:`.charting`), traced
over that grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._display import Row, num
from .._lazy import lazy_module
from ..estimate import Estimate, enforce
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .charting import Chart, Codim2, Curve, CurvePoint, HeatMap, dedupe, sweep_config, trace  # noqa: F401  (re-exported)
from .continuation import continuation
from .equilibria import equilibrium
from .flow_compiled import CompiledFlow, flow_seconds
from .parameters import get_param, with_param
from .sensitivity import locate_fold, stick_slip_margin

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick

CURVES = ("hopf", "grazing", "fold")


@dataclass(repr=False, eq=False)
class StabilityChart(Chart):
    """Curves in the (x, y) plane of two parameters (found in y at each x of a grid), codimension-two points,
    and optionally a sweep heat map.

    Its fields, shared by every chart, are listed below.
    """

    FIELDS = {"hopf": {"l1": float, "criticality": str}, "grazing": {"stick_slip_below": bool},
              "fold": {"X": float, "vr_min": float}, "fold_at_grazing": {"smooth": bool}}

    def _notes(self) -> list[Row]:
        return [("codim 2", "; ".join(f"{p.kind} at {self.x_param}={num(p.x)}, {self.y_param}={num(p.y)}"
                                      for p in self.codim2) or "none")]


@dataclass
class _Source:
    """What every autonomous curve source knows: the system and the two parameters of the plane."""

    model: BeltOscillator
    law: FrictionLaw
    xp: str
    yp: str

    def at_point(self, x: float, y: float) -> tuple[BeltOscillator, FrictionLaw]:
        return with_param(*with_param(self.model, self.law, self.xp, x), self.yp, y)


# -- the Hopf curve -------------------------------------------------------------------------
def third_derivative(law: FrictionLaw, s: float) -> float:
    """The slip curve's third derivative at s: central second differences of its slope, Richardson-extrapolated (error ~h^4)."""

    def d2(h: float) -> float:
        return (law.slip_slope(s + h) - 2.0 * law.slip_slope(s) + law.slip_slope(s - h)) / (h * h)

    h = 2e-3 * max(abs(s), 1e-9)
    return (4.0 * d2(0.5 * h) - d2(h)) / 3.0


def lyapunov_coefficient(model: BeltOscillator, law: FrictionLaw) -> float:
    """l1 = -F'''(V_b) / 16 of the Hopf point (negative: supercritical)."""
    return -third_derivative(law, abs(model.vb)) / 16.0


def _trace(model, law, xp, yp, x, y) -> float:
    m, lw = with_param(*with_param(model, law, xp, x), yp, y)
    eq = equilibrium(m, lw)
    return math.nan if eq is None else -eq.damping


def _roots(f, ys: np.ndarray, tol: float) -> list[float]:
    """Sign changes of f on the scan ``ys``, refined by brentq."""
    vals = [f(float(y)) for y in ys]
    out = []
    for a, b, fa, fb in zip(ys[:-1], ys[1:], vals[:-1], vals[1:]):
        if math.isfinite(fa) and math.isfinite(fb) and fa * fb < 0:
            out.append(float(optimize.brentq(f, float(a), float(b), xtol=tol, rtol=4 * np.finfo(float).eps)))
        elif fb == 0.0:
            out.append(float(b))
    return out


@dataclass
class _Hopf(_Source):
    """Hopf points at each x: the roots in y of the trace on the scan ``ys``, with their criticality."""

    ys: np.ndarray  # the scan of y whose sign changes are refined

    def at(self, index: int, x: float) -> list[tuple[str, CurvePoint]]:
        tol = 1e-14 * max(abs(self.ys[0]), abs(self.ys[-1]), 1e-300)
        out = []
        for y in _roots(lambda y: _trace(self.model, self.law, self.xp, self.yp, x, y), self.ys, tol):
            l1 = lyapunov_coefficient(*self.at_point(x, y))
            out.append(("hopf", CurvePoint(x, y, {"l1": l1, "criticality": "supercritical" if l1 < 0 else "subcritical"})))
        return out

    def curves(self, found: dict[str, list[CurvePoint]]) -> tuple[list[Curve], list[Codim2]]:
        pts = found.get("hopf", [])
        return [Curve("hopf", pts)], _bautin(self.model, self.law, self.xp, self.yp, pts, self.ys)


def hopf_curve(model: BeltOscillator, law: FrictionLaw, xp: str, yp: str, xs, ys) -> tuple[Curve, list[Codim2]]:
    """The Hopf curve on the x grid (roots in y of the trace on the scan ``ys``), its criticality and Bautin points."""
    (curve,), bautin = trace([_Hopf(model, law, xp, yp, np.asarray(ys, dtype=float))], np.asarray(xs, dtype=float))
    return curve, bautin


def _bautin(model, law, xp, yp, pts: list[CurvePoint], ys) -> list[Codim2]:
    """Sign changes of l1 between Hopf points at neighbouring x (and close y), refined along the curve."""
    out = []
    for a, b in zip(pts[:-1], pts[1:]):
        if a.x == b.x or a.detail["l1"] * b.detail["l1"] >= 0:
            continue
        lo_y, hi_y = sorted((a.y, b.y))
        pad = 0.5 * (hi_y - lo_y) + 1e-6 * (ys[-1] - ys[0])

        def y_hopf(x: float) -> float:
            f = lambda y: _trace(model, law, xp, yp, x, y)
            return optimize.brentq(f, max(ys[0], lo_y - pad), min(ys[-1], hi_y + pad), xtol=1e-15, rtol=4 * np.finfo(float).eps)

        def l1(x: float) -> float:
            m, lw = with_param(*with_param(model, law, xp, x), yp, y_hopf(x))
            return lyapunov_coefficient(m, lw)

        try:
            xb = float(optimize.brentq(l1, a.x, b.x, xtol=1e-14 * max(abs(a.x), abs(b.x)), rtol=4 * np.finfo(float).eps))
            out.append(Codim2("bautin", xb, float(y_hopf(xb)), {"criticality_below": a.detail["criticality"] if a.x < b.x else b.detail["criticality"]}))
        except ValueError:
            continue
    return out


# -- the grazing curve ------------------------------------------------------------------------
@dataclass
class _Grazing(_Source):
    """Grazing points at each x: the roots in y of the stick-slip margin on the scan ``ys``."""

    ys: np.ndarray  # the scan of y whose sign changes are refined

    def margin(self, x: float, y: float) -> float:
        try:
            return stick_slip_margin(*self.at_point(x, y), self.yp)[0]
        except (RuntimeError, ValueError):
            return math.nan

    def at(self, index: int, x: float) -> list[tuple[str, CurvePoint]]:
        ys = self.ys
        tol = 1e-14 * max(abs(ys[0]), abs(ys[-1]), 1e-300)
        out = []
        for y in _roots(lambda y: self.margin(x, y), ys, tol):
            below = self.margin(x, y - 1e-6 * (ys[-1] - ys[0]))
            out.append(("grazing", CurvePoint(x, y, {"stick_slip_below": bool(below < 0)})))
        return out

    def curves(self, found: dict[str, list[CurvePoint]]) -> tuple[list[Curve], list[Codim2]]:
        return [Curve("grazing", found.get("grazing", []))], []


def grazing_curve(model: BeltOscillator, law: FrictionLaw, xp: str, yp: str, xs, ys) -> Curve:
    """Where the stick-slip cycle's slip excursion touches the belt speed (roots in y of the stick-slip margin)."""
    (curve,), _ = trace([_Grazing(model, law, xp, yp, np.asarray(ys, dtype=float))], np.asarray(xs, dtype=float))
    return curve


# -- fold curves ---------------------------------------------------------------------------------
@dataclass
class _Folds(_Source):
    """Fold curves of cycles: seeds from continuations in y at every ``every``-th x, each followed along the grid."""

    xs: np.ndarray  # the whole grid: a fold found at one x is followed along all of it
    y_range: tuple[float, float]
    every: int
    continuation: dict[str, Any]  # keywords of the seeding continuations

    def at(self, index: int, x: float) -> list[tuple[str, CurvePoint]]:
        """Smooth folds (with their X) as ``seed`` and folds at grazing corners found by the continuation at x."""
        if index % self.every:
            return []
        m, lw = with_param(self.model, self.law, self.xp, x)
        try:
            res = continuation(m, lw, self.yp, self.y_range[0], self.y_range[1], **self.continuation)
        except (RuntimeError, ValueError):
            return []
        out = []
        for b in res.bifurcations:
            if b.type != "fold":
                continue
            detail = dict(b.detail)
            if detail.get("smooth") and b.branch is not None:
                near = min(res.branches[b.branch].points, key=lambda p: abs(p.value - b.value))
                try:
                    detail["X"], _ = locate_fold(m, lw, self.yp, near.x, b.value)
                except (RuntimeError, ValueError, np.linalg.LinAlgError):
                    continue
                out.append(("seed", CurvePoint(x, float(b.value), detail)))
            elif not detail.get("smooth"):
                out.append(("fold_at_grazing", CurvePoint(x, float(b.value), detail)))
        return out

    def curves(self, found: dict[str, list[CurvePoint]]) -> tuple[list[Curve], list[Codim2]]:
        """Each seed's fold followed along the x grid (once per curve); where its smallest V_r changes sign, a
        fold-grazing point."""
        model, law, xp, yp, y_range = self.model, self.law, self.xp, self.yp, self.y_range
        tol = 1e-6 * (y_range[1] - y_range[0])
        pts: list[CurvePoint] = []
        followed: list[tuple[float, float]] = []
        codim: list[Codim2] = []
        for seed in found.get("seed", []):
            if any(x == seed.x and abs(y - seed.y) <= 1e3 * tol for x, y in followed):
                continue  # on a curve already followed
            curve = _follow_fold(model, law, xp, yp, self.xs, seed, y_range)
            followed += [(x, y) for x, _, y, _ in curve]
            pts += [CurvePoint(x, y, {"X": X, "vr_min": vr}) for x, X, y, vr in curve if vr > 0]
            for a, b in zip(curve[:-1], curve[1:]):
                if a[3] * b[3] < 0:
                    codim.append(_fold_grazing_point(model, law, xp, yp, a, b))
        corner = dedupe(found.get("fold_at_grazing", []), 1e-4 * (y_range[1] - y_range[0]))
        return [Curve("fold", dedupe(pts, tol)), Curve("fold_at_grazing", corner)], codim


def _fold_point(model, law, xp, yp, x, X, y):
    """The fold of the slip-only family (continued through V_r = 0) at x near (X, y): (X, y, smallest V_r)."""
    m, lw = with_param(model, law, xp, x)
    X, y = locate_fold(m, lw, yp, X, y, virtual=True)
    mm, ll = with_param(m, lw, yp, y)
    return X, y, CompiledFlow(mm, ll, virtual=True).run((X, 0.0), returns=1).vr_min


def _follow_fold(model, law, xp, yp, xs, seed: CurvePoint, y_range) -> list[tuple[float, float, float, float]]:
    """The fold curve through ``seed`` on the x grid, both ways: (x, X, y, smallest V_r) per x.

    Between grid values it steps with a secant predictor, halving the step
    where Newton fails (down to 1/64 of the grid step).
    """
    i0 = int(np.argmin(np.abs(xs - seed.x)))
    out = {}
    for direction in (1, -1):
        cur = (float(xs[i0]), seed.detail["X"], seed.y)
        slope = None  # d(X, y)/dx of the last step
        i = i0
        while 0 <= i < len(xs):
            target = float(xs[i])
            ok = True
            while cur[0] != target:
                dx = target - cur[0]
                for _ in range(7):
                    x = cur[0] + dx
                    X, y = (cur[1] + slope[0] * dx, cur[2] + slope[1] * dx) if slope else (cur[1], cur[2])
                    try:
                        Xn, yn, vr = _fold_point(model, law, xp, yp, x, X, y)
                        break
                    except (RuntimeError, ValueError, np.linalg.LinAlgError):
                        dx *= 0.5
                else:
                    ok = False
                    break
                slope = ((Xn - cur[1]) / dx, (yn - cur[2]) / dx)
                cur = (x, Xn, yn)
                if not (y_range[0] <= yn <= y_range[1]) or not math.isfinite(Xn):
                    ok = False
                    break
            if not ok:
                break
            if i not in out:
                try:
                    Xn, yn, vr = _fold_point(model, law, xp, yp, cur[0], cur[1], cur[2])
                except (RuntimeError, ValueError, np.linalg.LinAlgError):
                    break
                out[i] = (cur[0], Xn, yn, vr)
            i += direction
    return [out[k] for k in sorted(out)]


def fold_curves(model: BeltOscillator, law: FrictionLaw, xp: str, yp: str, xs, y_range: tuple[float, float], *,
                seed_every: int = 4, **kw) -> tuple[Curve, Curve, list[Codim2]]:
    """Fold curves of cycles, the folds at grazing corners, and the fold-grazing points.

    Seeds come from one-parameter continuations in y (every ``seed_every``-th
    x); each seed's fold is followed along the whole x grid by Newton
    (:func:`~.sensitivity.locate_fold` on the slip-only family continued
    through V_r = 0, with a secant predictor).  A fold cycle whose smallest
    V_r is > 0 is a real one; where that margin changes sign the fold curve
    ends on the grazing curve -- a fold-grazing point, refined by brentq in x.
    """
    xs = np.asarray(xs, dtype=float)
    (fold, corner), codim = trace([_Folds(model, law, xp, yp, xs, tuple(y_range), seed_every, kw)], xs)
    return fold, corner, codim


def _fold_grazing_point(model, law, xp, yp, a, b) -> Codim2:
    """Where the fold cycle's smallest V_r crosses 0 between fold points a and b: the fold meets the grazing.

    Marches from a in sixteenths of the interval (Newton from the last fold)
    to a short bracket, then brentq in x.
    """
    last = (a[0], a[1], a[2], a[3])
    bracket = None
    for x in np.linspace(a[0], b[0], 17)[1:]:
        try:
            X, y, vr = _fold_point(model, law, xp, yp, float(x), last[1], last[2])
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            break
        if vr * last[3] < 0:
            bracket = (last, (float(x), X, y, vr))
            break
        last = (float(x), X, y, vr)
    if bracket is None:
        return Codim2("fold_grazing", 0.5 * (a[0] + b[0]), 0.5 * (a[2] + b[2]), {"located": False, "between": [a[0], b[0]]})
    lo, hi = bracket
    found = [lo[1], lo[2]]

    def margin(x: float) -> float:
        X, y, vr = _fold_point(model, law, xp, yp, x, lo[1], lo[2])
        found[:] = [X, y]
        return vr

    xg = float(optimize.brentq(margin, lo[0], hi[0], xtol=1e-13 * max(abs(lo[0]), abs(hi[0])), rtol=4 * np.finfo(float).eps))
    margin(xg)
    return Codim2("fold_grazing", xg, found[1], {"located": True, "X": found[0]})


# -- the chart -----------------------------------------------------------------------------------
def stability_chart(
    model: BeltOscillator,
    law: FrictionLaw,
    x_param: str,
    x_values,
    y_param: str,
    y_range: tuple[float, float],
    *,
    curves: tuple[str, ...] = CURVES,
    n_scan: int = 201,
    fold_seeds: tuple[str, ...] = ("hopf", "start", "stop"),
    fold_every: int = 2,
    sweep: Any = None,
    heat: str = "R_c",
) -> StabilityChart:
    """The Hopf, grazing and fold curves in the (x_param, y_param) plane.

    Parameters
    ----------
    model, law:
        The oscillator and its friction law at the other parameters' values.
    x_param, y_param:
        The parameters of the plane's axes (``vb``, ``zeta``, or a parameter of the law).
    x_values:
        The grid of the first parameter.
    y_range, n_scan:
        The interval of the second and the number of scan points in it (roots
        closer than a scan step may be missed; each found root is refined to rounding).
    curves:
        Which curves (``hopf``, ``grazing``, ``fold``).
    fold_seeds, fold_every:
        Seeds of the continuations in y that find folds, and every how many x values one runs (each fold
        found is then followed along the whole x grid).
    sweep, heat:
        An xarray dataset of simulations on the same plane (from
        :func:`frictionflow.sweep.run_sweep`) and the variable to draw under the curves.
    """
    for c in curves:
        if c not in CURVES:
            raise ValueError(f"curves must be among {', '.join(CURVES)}, got {c!r}")
    refuse_internal_state(law)
    get_param(model, law, x_param)
    get_param(model, law, y_param)
    if x_param == y_param:
        raise ValueError("the two parameters must differ")
    xs = np.asarray(x_values, dtype=float)
    enforce(chart_estimate(law, len(xs), n_scan, curves, fold_every))  # within the limits in force, if any
    lo, hi = float(min(y_range)), float(max(y_range))
    ys = np.linspace(lo, hi, n_scan)
    plane = (model, law, x_param, y_param)
    sources: list[Any] = []
    if "hopf" in curves:
        sources.append(_Hopf(*plane, ys))
    if "grazing" in curves and law.stick_rule == "switch":  # without a stick phase there is nothing to graze
        sources.append(_Grazing(*plane, ys))
    if "fold" in curves and not law.piecewise_constant:  # a constant slip force has no smooth cycle family to fold
        sources.append(_Folds(*plane, xs, (lo, hi), fold_every, {"seeds": fold_seeds, "n_equilibria": 21}))
    out_curves, codim = trace(sources, xs)
    return StabilityChart(x_param, y_param, xs, (lo, hi), {**model.report(), **law.as_dict()}, out_curves, codim,
                          sweep=sweep, heat=heat if sweep is not None else "")


def refuse_internal_state(law: FrictionLaw) -> None:
    """One line (ValueError) for a law with an internal state: the chart's curves follow the slip curve of the
    state (X, X') alone, which such a law does not have (its Hopf points are the whole state's)."""
    if law.internal_names:
        raise ValueError(f"friction: stability charts take laws without an internal state; {law.name} has "
                         f"{', '.join(law.internal_names)} (continue finds its Hopf points and orbits on the whole state)")


def chart_estimate(law: FrictionLaw, n_x: int, n_scan: int, curves: tuple[str, ...], fold_every: int) -> Estimate:
    """The compiled orbit flows of the curves: one per scan point and x for the grazing curve, and as many per
    fold seed (a bound for the continuations in y that seed the folds; the Hopf curve needs none).

    A flow's cost: :func:`~.flow_compiled.flow_seconds`.
    """
    grazing = "grazing" in curves and law.stick_rule == "switch"
    folds = "fold" in curves and not law.piecewise_constant
    flows = float(n_x * n_scan) * (grazing + folds / fold_every)
    return Estimate(flows, "orbit flows", flows * flow_seconds(law))


def stability_map(
    model: BeltOscillator,
    law: FrictionLaw,
    x_param: str,
    x_values,
    y_param: str,
    y_range: tuple[float, float],
    *,
    sweep_shape: tuple[int, int] | None = None,
    sweep_out: Any = None,
    t_end: float = 500.0,
    heat: str = "R_c",
    sweep_name: str = "sweep_out",
    **kw: Any,
) -> StabilityChart:
    """:func:`stability_chart` with a heat map from a sweep of simulations over the same plane.

    Parameters
    ----------
    model, law, x_param, x_values, y_param, y_range:
        The system and the plane, as :func:`stability_chart`.
    sweep_shape:
        (n_x, n_y), the sweep's grid (None: no sweep), run by
        :func:`frictionflow.sweep.run_sweep`.
    sweep_out:
        Where the sweep is written (.zarr or .nc; default a temporary .nc).
    t_end:
        Length of each simulation of the sweep.
    heat:
        The sweep variable drawn under the curves (R_c, TR_B, ...).
    sweep_name:
        How messages name ``sweep_out`` (the command line passes its option, ``--store``).
    **kw:
        Passed on to :func:`stability_chart`.
    """
    refuse_internal_state(law)  # before the sweep under the curves runs
    heat_map, x_range = HeatMap(sweep_shape, sweep_out, t_end, heat, sweep_name), (x_values[0], x_values[-1])
    curves = chart_estimate(law, len(x_values), kw.get("n_scan", 201), kw.get("curves", CURVES), kw.get("fold_every", 2))
    sweep_cost = heat_map.estimate(model, law, x_param, x_range, y_param, y_range)
    enforce(curves if sweep_cost is None else curves.then(sweep_cost))  # within the limits in force, if any
    sweep = heat_map.run(model, law, x_param, x_range, y_param, y_range)
    return stability_chart(model, law, x_param, x_values, y_param, y_range, sweep=sweep, heat=heat, **kw)
