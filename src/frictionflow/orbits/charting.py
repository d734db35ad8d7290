"""The two-parameter chart engine: curves traced over a grid of one parameter, the chart result, the heat map.

A chart lives in the plane of two parameters (``x``, ``y``).  One of them is
a *grid* (``grid_axis``): at each of its values a **curve source** finds the
points of its codimension-one curves along the other parameter (the *span*),
and :func:`trace` collects them, one source at a time over the whole grid
(a source may carry what it found at one value to the next), into curves
(:class:`Curve`, joined by kind) and codimension-two points (:class:`Codim2`).

* The autonomous chart (:mod:`.chart`) grids ``x`` and finds Hopf, grazing
  and fold points in ``y``.
* The forced chart (:mod:`.forced_chart`) grids ``y`` and continues the
  forced orbits in ``x`` at each value; its continuation's events are the points.

:class:`Chart` is the result of both (with its summary, JSON, dataset and
figure, :func:`~frictionflow.orbits.chart_plot.plot_chart`), :func:`dedupe` drops a point
found twice at one grid value, and :class:`HeatMap` runs the sweep of
simulations drawn under the curves.
"""

from __future__ import annotations

import json
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Protocol, Sequence

import numpy as np

from .._display import Row, Summarized, num
from .._figures import draw
from .._json import jsonable
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..sweep.compute import VARIABLES
from ..estimate import Estimate
from ..parameters import declared
from ..sweep.config import parse_sweep
from ..sweep.runner import run_sweep, sweep_estimate


@dataclass
class CurvePoint:
    """One point of a curve: (x, y) and what else is known there.

    Attributes
    ----------
    x:
        The value of the chart's x parameter (:attr:`Chart.x_param`) at the point.
    y:
        The value of the chart's y parameter (:attr:`Chart.y_param`) at the point.
    detail:
        What else was found there, by name; written beside ``x`` and ``y``
        into the chart's JSON and dataset (the fields :attr:`Chart.FIELDS`
        declares for the curve's kind, and any others).  On the autonomous
        chart: ``l1`` (the first Lyapunov coefficient) and ``criticality``
        (``supercritical`` or ``subcritical``) on a Hopf curve;
        ``stick_slip_below`` (whether the period-1 stick-slip cycle exists
        just below the point in y) on a grazing curve; ``X`` and ``vr_min``
        (the fold cycle's X and smallest V_r) on a fold curve; the
        continuation's details (``smooth``: False) at a fold at a grazing
        corner.  On the forced chart: the orbits' period ``m``, the state
        ``X``, ``V`` (X') at tau = 0, the Floquet ``multipliers`` as [re, im]
        pairs, and the event's own details (``smooth``, ``angle``,
        ``stick_phase``, ``slip_reversal``, ``at``) where it has them.
    """

    x: float
    y: float
    detail: dict[str, Any] = field(default_factory=dict)


@dataclass
class Curve:
    """A codimension-one curve in the (x, y) parameter plane.

    Attributes
    ----------
    kind:
        What happens on the curve: ``hopf``, ``grazing``, ``fold`` or
        ``fold_at_grazing`` on the autonomous chart; ``fold``,
        ``period_doubling``, ``neimark_sacker`` or ``grazing`` (of the
        m-period orbits) on the forced chart.
    points:
        The points found, in grid order (several at one grid value where the
        curve crosses the span more than once).
    m:
        For a forced chart's curve, the period of its orbits in forcing
        periods; None on the autonomous chart.
    """

    kind: str
    points: list[CurvePoint]
    m: int | None = None  # forced curves: the period of their orbits in forcing periods

    def xy(self) -> np.ndarray:
        return np.array([[p.x, p.y] for p in self.points]).reshape(-1, 2)

    def to_dict(self) -> dict[str, Any]:
        out = {"kind": self.kind, "points": [{"x": p.x, "y": p.y, **p.detail} for p in self.points]}
        if self.m is not None:
            out["m"] = self.m
        return out


@dataclass
class Codim2:
    """A codimension-two point: ``bautin`` (a Hopf point changing criticality) or ``fold_grazing``.

    Attributes
    ----------
    kind:
        ``bautin`` (the first Lyapunov coefficient of the Hopf curve changes
        sign) or ``fold_grazing`` (the fold of cycles meets the grazing: the
        fold cycle's smallest V_r reaches 0).
    x:
        The value of the chart's x parameter at the point.
    y:
        The value of the chart's y parameter at the point.
    detail:
        What else is known there, by name, written beside ``x`` and ``y``
        into the chart's JSON: for ``bautin``, ``criticality_below`` (the
        Hopf criticality at the smaller x); for ``fold_grazing``,
        ``located`` (whether it was refined by root finding) with the fold
        cycle's ``X`` there, or, when not located, ``between`` (the two grid
        values of x it lies between; x and y are then the midpoints).
    """

    kind: str
    x: float
    y: float
    detail: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "x": self.x, "y": self.y, **self.detail}


# -- tracing curves over the grid --------------------------------------------------------------------
class CurveSource(Protocol):
    """One family of curves over the grid: the autonomous Hopf, grazing or fold curves, the forced m-period orbits."""

    def at(self, index: int, value: float) -> list[tuple[str, CurvePoint]]:
        """The points found along the span at the ``index``-th grid value, each with its curve's kind."""

    def curves(self, found: dict[str, list[CurvePoint]]) -> tuple[list[Curve], list[Codim2]]:
        """The curves that the points found over the whole grid (by kind, in grid order) make, and codim-2 points."""


def trace(sources: Sequence[CurveSource], grid: np.ndarray) -> tuple[list[Curve], list[Codim2]]:
    """The curves and codimension-two points of ``sources``, each run over every value of ``grid`` in turn.

    One source runs over the whole grid before the next starts: a source
    that continues a family of orbits starts each value from the last one's.
    """
    curves: list[Curve] = []
    codim2: list[Codim2] = []
    for source in sources:
        found: dict[str, list[CurvePoint]] = {}
        for i, value in enumerate(grid):
            for kind, point in source.at(i, float(value)):
                found.setdefault(kind, []).append(point)
        more, codim = source.curves(found)
        curves += more
        codim2 += codim
    return curves, codim2


def dedupe(points: list[CurvePoint], tol: float, grid_axis: str = "x") -> list[CurvePoint]:
    """One point per (grid value, span value within ``tol``) found more than once.

    Several seeds of one continuation, or the continuations both ways from
    one start, meet the same point at one grid value.
    """
    on_grid, along = ("x", "y") if grid_axis == "x" else ("y", "x")
    out: list[CurvePoint] = []
    for p in points:
        g, s = getattr(p, on_grid), getattr(p, along)
        if not any(getattr(q, on_grid) == g and abs(getattr(q, along) - s) <= tol for q in out):
            out.append(p)
    return out


#: what a point's field holds to be stored as a number
NUMBERS = (bool, int, float, np.bool_, np.integer, np.floating)


def _param_attrs(name: str) -> dict[str, str]:
    """The units and long name of parameter ``name`` as declared (:mod:`frictionflow.parameters`), if it is."""
    p = declared().get(name)
    return dict(p.attrs) if p is not None else {"long_name": name}


def _field_table(rows: list[list[CurvePoint]], n: int, key: str, kind: type | None = None) -> tuple[np.ndarray, dict]:
    """Field ``key`` of the points (rows: per grid value, in root order) as an (n_grid, n) array and its attributes:
    numbers (and flags, 1 true / 0 false) as floats, NaN where there is no value; text as text (variable-length),
    "" there; anything else (lists) as its JSON.  ``kind`` (float, bool, str): the field's declared type, which
    decides when no point has it."""
    given = [p.detail[key] for row in rows for p in row if key in p.detail]
    flags = kind is bool if not given else all(isinstance(v, (bool, np.bool_)) for v in given)
    numbers = kind in (None, float, bool) if not given else all(isinstance(v, NUMBERS) for v in given)
    if numbers:
        table, fill, convert = np.full((len(rows), n), np.nan), np.nan, float
    else:
        table, fill = np.full((len(rows), n), "", dtype=object), ""
        convert = str if all(isinstance(v, str) for v in given) else (lambda v: json.dumps(jsonable(v)))
    for i, row in enumerate(rows):
        for j, p in enumerate(row):
            table[i, j] = convert(p.detail[key]) if key in p.detail else fill
    return table, ({"flag_values": [0, 1], "flag_meanings": "false true"} if numbers and flags else {})


# -- the chart ---------------------------------------------------------------------------------------
@dataclass(repr=False, eq=False)
class Chart(Summarized):
    """Curves in the (x, y) plane of two parameters, traced over a grid of one of them, and optionally a heat map.

    ``grid`` holds the values of the ``grid_axis`` parameter, ``span`` the
    interval of the other one.  ``continued_in`` names the parameter each
    grid value's continuation ran in when the points are its events (their
    ``runs`` recorded), "" otherwise.
    """

    #: the parameter of the plane's x axis
    x_param: str
    #: the parameter of the plane's y axis
    y_param: str
    #: the values of the ``grid_axis`` parameter the curves were traced at
    grid: np.ndarray
    #: the interval of the other parameter
    span: tuple[float, float]
    #: every other parameter's value (the oscillator's and the law's)
    params: dict[str, Any]
    #: the curves found, each with its kind and its points
    curves: list[Curve]
    #: the codimension-two points where curves meet or change character
    codim2: list[Codim2] = field(default_factory=list)
    #: the continuation run at each grid value, when the points are its events (else empty)
    runs: list[Any] = field(default_factory=list)
    #: an ``xarray.Dataset`` of simulations on the plane, or None
    sweep: Any = None
    #: the sweep variable drawn under the curves ("" without a sweep)
    heat: str = ""
    #: which parameter ``grid`` holds, ``x`` or ``y``
    grid_axis: str = "x"
    #: the parameter each grid value's continuation ran in, "" otherwise
    continued_in: str = ""
    #: per curve kind, the fields its points carry (by name; each a float, bool or str), in the dataset even without points
    FIELDS: ClassVar[dict[str, dict[str, type]]] = {}

    @property
    def x_values(self) -> np.ndarray:
        """The grid of x, or the ends of its span."""
        return np.asarray(self.grid if self.grid_axis == "x" else self.span, dtype=float)

    @property
    def y_range(self) -> tuple[float, float]:
        """The span of y, or the ends of its grid."""
        return self.span if self.grid_axis == "x" else (float(np.min(self.grid)), float(np.max(self.grid)))

    def curve(self, kind: str, m: int | None = None) -> Curve | None:
        return next((c for c in self.curves if c.kind == kind and (m is None or c.m == m)), None)

    def _names(self) -> tuple[str, str]:
        """(grid parameter, span parameter)."""
        return (self.x_param, self.y_param) if self.grid_axis == "x" else (self.y_param, self.x_param)

    def _plane(self) -> str:
        gp, sp = self._names()
        grid = f"{gp} from {num(float(self.grid[0]))} to {num(float(self.grid[-1]))} ({len(self.grid)} values)"
        span = f"{sp} in [{num(self.span[0])}, {num(self.span[1])}]" + (" (continued)" if self.continued_in else "")
        return f"{grid} x {span}" if self.grid_axis == "x" else f"{span} x {grid}"

    def _notes(self) -> list[Row]:
        """Rows between the curves and the heat map (each kind of chart says what else it found)."""
        return []

    def _summary(self) -> tuple[str, list[Row]]:
        curves = "; ".join(f"{c.kind}{'' if c.m is None else f' m={c.m}'} ({len(c.points)} points)" for c in self.curves)
        rows = [("plane", self._plane()), ("curves", curves or "none"), *self._notes()]
        if self.sweep is not None:
            rows.append(("heat map", f"{self.heat} from {int(np.prod([len(self.sweep[d]) for d in self.sweep[self.heat].dims]))} simulations"))
        return type(self).__name__, rows

    def to_dict(self) -> dict[str, Any]:
        axes = ({"x_values": self.grid, "y_range": list(self.span)} if self.grid_axis == "x"
                else {"x_range": list(self.span), "y_values": self.grid})
        continued = {"continued_in": self.continued_in} if self.continued_in else {}
        runs = {"runs": [r.to_dict() for r in self.runs]} if self.continued_in else {}
        return jsonable({
            "x_param": self.x_param, "y_param": self.y_param, **axes, "params": self.params, **continued,
            "curves": [c.to_dict() for c in self.curves], "codim2": [p.to_dict() for p in self.codim2], **runs,
            "heat": self.heat or None,
        })

    def to_xarray(self):
        """Each curve as its span parameter over (grid, root) -- the k-th root at each grid value, NaN where
        fewer -- and each field its points carry (``l1``, ``criticality``, ...) as a variable of the same shape
        (``{curve}_{field}``: NaN, or "" for text, where a curve has no point), with the sweep's variables (on its
        own (x, y) grid) alongside.  The grid's coordinate has its parameter's units and long name; the
        attributes ``params`` and ``codim2`` are JSON."""
        import xarray as xr

        gp, sp = self._names()
        data = {}
        for c in self.curves:
            data.update(self._curve_variables(c, gp, sp))
        ds = xr.Dataset(data, coords={gp: (gp, np.asarray(self.grid, dtype=float), _param_attrs(gp))})
        along = "y" if self.grid_axis == "x" else "x"
        found = ({"continued_in": self.continued_in, f"{along}_range": list(self.span)} if self.continued_in
                 else {"codim2": json.dumps(jsonable([p.to_dict() for p in self.codim2]))})
        ds.attrs.update({"x_param": self.x_param, "y_param": self.y_param, **found,
                         "params": json.dumps(jsonable(self.params))})
        if self.sweep is not None:
            sw = self.sweep.rename({d: f"sweep_{d}" for d in self.sweep.dims})
            for k, v in sw.data_vars.items():
                ds[f"sweep_{k}"] = v
        return ds

    def _curve_variables(self, c: Curve, gp: str, sp: str) -> dict[str, tuple]:
        """Curve ``c``'s variables over (grid, root): its span values and each field of its points, in root order."""
        on_grid, along = ("x", "y") if self.grid_axis == "x" else ("y", "x")
        per_value: dict[float, list[CurvePoint]] = {}
        for p in c.points:
            per_value.setdefault(getattr(p, on_grid), []).append(p)
        rows = [sorted(per_value.get(float(g), []), key=lambda p: getattr(p, along)) for g in self.grid]
        n = max([1, *(len(r) for r in rows)])
        name = c.kind if c.m is None else f"{c.kind}_m{c.m}"
        dims, orbits = (gp, f"{name}_root"), ("" if c.m is None else f" of the m={c.m} orbits")
        span = np.full((len(rows), n), np.nan)
        for i, row in enumerate(rows):
            span[i, :len(row)] = [getattr(p, along) for p in row]
        units = {"units": _param_attrs(sp)["units"]} if "units" in _param_attrs(sp) else {}
        out = {f"{name}_{sp}": (dims, span, {"long_name": f"{sp} on the {c.kind} curve{orbits}", **units})}
        declared_fields = self.FIELDS.get(c.kind, {})
        for key in dict.fromkeys([*declared_fields, *(k for p in c.points for k in p.detail)]):
            values, attrs = _field_table(rows, n, key, declared_fields.get(key))
            out[f"{name}_{key}"] = (dims, values, {"long_name": f"{key} at each point of the {c.kind} curve{orbits}",
                                                   **attrs})
        return out

    def plot(self, path: Any = None, **options: Any):
        """The curves over the sweep heat map (:func:`~frictionflow.orbits.chart_plot.plot_chart`).

        ``options``: the figure function's keywords (``dpi``: dots per inch, ``name``).
        """
        return draw(self, path, **options)


# -- the heat map under the curves ---------------------------------------------------------------------
def sweep_config(model: BeltOscillator, law: FrictionLaw, x_param: str, x_range, y_param: str, y_range,
                 shape: tuple[int, int], t_end: float = 500.0) -> dict[str, Any]:
    """The config of a :func:`frictionflow.sweep.run_sweep` over the chart's plane (the other parameters fixed)."""
    fixed = {k: v for k, v in {**model.report(), **law.as_dict()}.items() if k not in (x_param, y_param)}
    return {**fixed, "t_end": float(t_end), "grid": {
        x_param: {"start": float(min(x_range)), "stop": float(max(x_range)), "num": int(shape[0])},
        y_param: {"start": float(min(y_range)), "stop": float(max(y_range)), "num": int(shape[1])}}}


@dataclass(frozen=True)
class HeatMap:
    """The sweep of simulations drawn under a chart's curves.

    ``shape`` (n_x, n_y): its grid (None: no sweep); ``out``: where
    :func:`frictionflow.sweep.run_sweep` writes it (.zarr or .nc; None: a
    temporary .nc); ``heat``: the sweep variable drawn (R_c, TR_B, ...); ``name``: how messages name ``out``
    (the command line's option).
    """

    shape: tuple[int, int] | None = None
    out: Any = None
    t_end: float = 500.0
    heat: str = "R_c"
    name: str = "sweep_out"

    def estimate(self, model: BeltOscillator, law: FrictionLaw, x_param: str, x_range, y_param: str,
                 y_range) -> Estimate | None:
        """The sweep's estimate (:func:`~frictionflow.sweep.runner.sweep_estimate`), or None without a shape."""
        if self.shape is None:
            return None
        cfg = parse_sweep(sweep_config(model, law, x_param, x_range, y_param, y_range, self.shape, self.t_end))
        return sweep_estimate(cfg, self.out if self.out is not None else Path(tempfile.gettempdir()) / "sweep.nc",
                              self.name)

    def run(self, model: BeltOscillator, law: FrictionLaw, x_param: str, x_range, y_param: str, y_range):
        """The sweep over x_range by y_range (an xarray.Dataset, loaded), or None without a shape."""
        if self.shape is None:
            return None
        names = [v[0] for v in VARIABLES]
        if self.heat not in names:  # before the sweep and the chart: a bad name costs nothing
            raise ValueError(f"heat must be a sweep variable ({', '.join(names)}), got {self.heat!r}")
        cfg = sweep_config(model, law, x_param, x_range, y_param, y_range, self.shape, self.t_end)
        if self.out is not None:
            return run_sweep(cfg, self.out, name=self.name).load()
        with tempfile.TemporaryDirectory(prefix="ff_map_") as tmp:  # the store is the caller's only with out
            ds = run_sweep(cfg, Path(tmp) / "sweep.nc")
            loaded = ds.load()
            ds.close()
        return loaded
