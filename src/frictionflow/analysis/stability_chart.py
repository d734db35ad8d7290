"""Steady sliding's stability over two parameters: a growth-rate chart and its stability boundary.

For each value of the second parameter ``y`` the eigenvalues are followed
along the first, ``x``, by :func:`~.stability.stability_scan`: every change
of sign of a mode's real part on that line is located by ``brentq`` and
classified (mode coupling, negative damping, divergence) exactly as on one
line.  The chart keeps, at every grid point, the largest real part (the
growth rate of the most unstable mode, <= 0 where steady sliding is stable)
and its frequency, and the located points of every line: together they draw
the stability boundary in the (x, y) plane, each point labelled by its
mechanism.  The boundary is located along x only; a boundary running parallel
to x is seen as the change of ``stable`` from one line to the next.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from .._display import Row, Summarized, num
from .._figures import draw
from .._json import jsonable
from .._progress import progress_bar
from ..core.assembly import Assembly
from ..estimate import Estimate
from ..friction.base import FrictionLaw
from .stability import Critical, StabilityScan, check_ends, scan_estimate, stability_scan, zero_tolerance


@dataclass(frozen=True)
class BoundaryPoint:
    """A critical point of one line of the chart.

    Attributes
    ----------
    y_value:
        The second parameter's value on that line.
    point:
        The critical point found along the line: its x value, kind, frequency and side.
    """

    y_value: float
    point: Critical

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``y_value`` and the critical point's ``value``, ``kind``, ``frequency``, ``unstable_above``."""
        return {"y_value": self.y_value, **self.point.to_dict()}


@dataclass(frozen=True, repr=False)
class StabilityChart(Summarized):
    """The eigenvalues of steady sliding over a grid of two parameters, and the located stability boundary.

    Attributes
    ----------
    x, y:
        The parameters' names (model entries such as ``contact.0.fd``, ``damper.0.c``).
    x_values, y_values:
        (P,) and (Q,) their values.
    growth:
        (Q, P) the largest real part of the eigenvalues at each grid point (row: a value of y); NaN where
        steady sliding is lost (a contact's normal load <= 0, or no isolated equilibrium).
    frequency:
        (Q, P) the imaginary part (>= 0) of that eigenvalue (the lowest of the modes tied with it at rounding,
        as the undamped modes of a stable undamped model are); NaN where steady sliding is lost.
    stable:
        (Q, P) bool: no eigenvalue in the right half plane (a real part within
        ``analysis.stability.zero_tolerance`` is zero, as on one line); False where steady
        sliding is lost.
    boundary:
        The critical points of every line along x, in the order of ``y_values`` then ``x_values``.
    """

    x: str
    y: str
    x_values: np.ndarray
    y_values: np.ndarray
    growth: np.ndarray
    frequency: np.ndarray
    stable: np.ndarray
    boundary: tuple[BoundaryPoint, ...] = field(default=())

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: names, values, ``growth``, ``frequency``, ``stable`` (rows over y) and ``boundary``; null
        growth and frequency where steady sliding is lost."""
        return jsonable({"x": self.x, "y": self.y, "x_values": self.x_values, "y_values": self.y_values,
                         "growth": self.growth, "frequency": self.frequency, "stable": self.stable,
                         "boundary": [b.to_dict() for b in self.boundary]})

    def plot(self, path: Any = None, **kwargs: Any) -> Any:
        """The growth-rate chart with the boundary (:func:`frictionflow.stability_plot.plot_stability_chart`)."""
        return draw(self, path, **kwargs)

    def _summary(self) -> tuple[str, list[Row]]:
        rows = [(name, f"{num(v[0])} .. {num(v[-1])} ({len(v)} values)")
                for name, v in ((self.x, self.x_values), (self.y, self.y_values))]
        rows.append(("stable at", f"{int(np.sum(self.stable))} of {self.stable.size} grid points (Re <= 0)"))
        kinds = sorted({b.point.kind for b in self.boundary})
        counts = ", ".join(f"{sum(b.point.kind == k for b in self.boundary)} {k}" for k in kinds)
        rows.append(("boundary", f"{len(self.boundary)} located points ({counts})" if self.boundary
                     else "none in the chart"))
        return "StabilityChart", rows


def _line_summary(scan: StabilityScan) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(growth, frequency, stable) along one line: the largest real part, its eigenvalue's |Im|, the scan's verdict.

    Modes whose real parts are that largest one within ``stability.zero_tolerance`` (the undamped modes of
    a stable undamped model, all at 0 up to rounding) are one tie: the lowest of their frequencies is given, not
    the one rounding happened to put first."""
    lam = scan.eigenvalues
    top = np.argmax(lam.real, axis=1)
    worst = lam[np.arange(len(lam)), top]
    with np.errstate(invalid="ignore"):  # (rows without steady sliding: NaN throughout, and they stay so)
        tied = lam.real >= worst.real[:, None] - zero_tolerance(lam)
        frequency = np.where(tied, np.abs(lam.imag), np.inf).min(axis=1)
    frequency[np.isnan(worst.real)] = np.nan
    return worst.real, frequency, scan.stable


def stability_chart(assembly_at: Callable[[float, float], Assembly], x_values: Sequence[float],
                    y_values: Sequence[float], *, x: str = "x", y: str = "y",
                    laws_at: Callable[[float, float], Sequence[FrictionLaw]] | None = None,
                    progress: bool = False) -> StabilityChart:
    """Eigenvalues of steady sliding over the grid ``x_values`` x ``y_values``, with the boundary located along x.

    Parameters
    ----------
    assembly_at:
        (x, y) -> the :class:`~frictionflow.core.assembly.Assembly` at those values.
    x_values:
        The first parameter's values, strictly monotone (at least 2): each line is a :func:`~.stability_scan`.
    y_values:
        The second parameter's values (at least 1, finite).
    x, y:
        The parameters' names, for the result and the messages.
    laws_at:
        (x, y) -> the contacts' law objects there; None: the slip values from the kernel rows.
    progress:
        Draw a progress bar over the lines on standard error.

    Returns
    -------
    StabilityChart
        Growth rate and frequency at every grid point, and the located critical points of every line.
    """
    ys = np.asarray(y_values, dtype=float).reshape(-1)
    if ys.size < 1 or not np.all(np.isfinite(ys)):
        raise ValueError(f"y_values must be at least 1 finite number, got {ys.size}")
    for yv in (float(ys[0]), float(ys[-1])):  # a bad end of y named before any line runs (a line checks x's)
        check_ends(lambda v, yv=yv: assembly_at(v, yv), x_values, f"{y} = {yv!r}, {x}",
                   None if laws_at is None else (lambda v, yv=yv: laws_at(v, yv)))
    scans = []
    with progress_bar(f"stability over {x} x {y}", len(ys), enabled=progress, unit="lines") as advance:
        for yv in map(float, ys):
            laws = None if laws_at is None else (lambda v, yv=yv: laws_at(v, yv))
            scans.append(stability_scan(lambda v, yv=yv: assembly_at(v, yv), x_values, param=x, laws_at=laws))
            advance(1)
    growth, freq, stable = (np.array(a) for a in zip(*(_line_summary(s) for s in scans)))
    boundary = tuple(BoundaryPoint(float(yv), c) for yv, s in zip(ys, scans) for c in s.critical)
    return StabilityChart(x, y, scans[0].values, ys, growth, freq, stable, boundary)


def chart_estimate(n: int, x_points: int, y_points: int) -> Estimate:
    """What :func:`stability_chart` of a structure with ``n`` dof over a ``x_points`` x ``y_points`` grid costs."""
    line = scan_estimate(n, x_points)
    return Estimate(line.work * y_points, line.unit, line.seconds * y_points, memory=line.memory * y_points)


__all__ = ["BoundaryPoint", "StabilityChart", "chart_estimate", "stability_chart"]
