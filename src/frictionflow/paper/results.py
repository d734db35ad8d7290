"""What every figure needs from one run, computed once per (point, solver).

A run of the paper's method records ~6e5 samples; the figures need only the
end of the run on a coarse grid, the averages over its last cycle, the
steady state found by :func:`~frictionflow.analysis.analyze` and the decay
rate of the cycle amplitudes.  :class:`Runner` computes these once per
(point, solver) and forgets the trajectory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis import analyze
from ..trajectory import Trajectory
from .runs import Point, run
from .settings import Settings
from .windows import Cycles, WindowAverages, tail

#: amplitudes below this are rounding noise on X ~ F_d, not motion
AMPLITUDE_FLOOR = 1e-13


@dataclass(frozen=True)
class PointResult:
    """One (point, solver): the shown end of the run, last-cycle averages and the steady state."""

    point: Point
    solver: str
    tau: np.ndarray
    x: np.ndarray
    v: np.ndarray
    fc: np.ndarray
    last: WindowAverages
    last_from_min: WindowAverages
    peaks: dict[str, float]
    kind: str
    period: float
    steady: dict[str, float]
    decay_rate: float
    t_terminal: float

    @property
    def p_f(self) -> np.ndarray:
        """Instantaneous friction power X' F_c on the shown grid."""
        return self.v * self.fc

    @property
    def p_dv(self) -> np.ndarray:
        """Instantaneous damper power 2 zeta X'^2 on the shown grid."""
        return 2.0 * self.point.zeta * self.v**2


def shown_grid(settings: Settings, t_end: float | None = None) -> np.ndarray:
    """The time grid of the shown end of a run (every ``shown_dt``)."""
    t_end = settings.t_end if t_end is None else t_end
    n = round(settings.shown_span / settings.shown_dt)
    return np.linspace(t_end - settings.shown_span, t_end, n + 1)


def decay_rate(cycles: Cycles, t_from: float = 0.0) -> float:
    """Exponential decay rate of the cycle amplitudes after ``t_from`` (least squares on log A).

    Positive: decaying.  Cycles whose amplitude is at the rounding floor are
    left out; NaN with fewer than three cycles.
    """
    s = cycles.starts("max")
    s = s[cycles.traj.t[s] >= t_from]
    if len(s) < 4:
        return math.nan
    a = cycles.averages(s)
    keep = a["amplitude"] > AMPLITUDE_FLOOR
    if keep.sum() < 3:
        return math.nan
    mids = 0.5 * (a["t0"] + a["t1"])
    slope = np.polyfit(mids[keep], np.log(a["amplitude"][keep]), 1)[0]
    return float(-slope)


def summarize(traj: Trajectory, point: Point, solver_name: str, settings: Settings, decay: bool = True) -> PointResult:
    """Reduce a run to a :class:`PointResult` (``decay=False``: skip the decay-rate fit, NaN)."""
    grid = shown_grid(settings, float(traj.t[-1]))
    # the shown span and the last cycles are all at the end: evaluate only there
    cycles = Cycles(tail(traj, grid[0] - 3 * 2 * math.pi))
    res = analyze(traj)
    ss = res.steady_state
    t_term = traj.extra.get("t_terminal")
    i0 = cycles.traj.index(grid[0])
    i1 = len(cycles.traj) - 1
    return PointResult(
        point=point,
        solver=solver_name,
        tau=grid,
        x=np.interp(grid, traj.t, traj.x),
        v=np.interp(grid, traj.t, traj.v),
        fc=np.interp(grid, traj.t, traj.fc),
        last=cycles.average(*cycles.last_cycle(at="max")),
        last_from_min=cycles.average(*cycles.last_cycle(at="min")),
        peaks=cycles.peaks(i0, i1),
        kind=ss.kind,
        period=math.nan if ss.period is None else float(ss.period),
        steady={
            "P_dv": res.power.P_dv,
            "P_fin": res.power.P_fin,
            "P_df": res.power.P_df,
            "R_c": res.power.R_c,
            "R_f": res.power.R_f,
            "TR_B": res.TR_B,
            "V_max": res.amplitude["V_max"],
            "X_min": res.amplitude["X_min"],
            "X_max": res.amplitude["X_max"],
            "energy_residual": res.energy_residual,
            "stick_fraction": math.nan if ss.stick_fraction is None else float(ss.stick_fraction),
        },
        # the first turns visit the band; the decay is measured on the free spiral after them
        decay_rate=decay_rate(Cycles(traj), t_from=min(50.0, 0.1 * float(traj.t[-1]))) if decay else math.nan,
        t_terminal=math.nan if t_term is None else float(t_term),
    )


class Runner:
    """Runs each (point, solver) at most once and keeps only its :class:`PointResult`."""

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self._cache: dict[tuple[Point, str, bool], PointResult] = {}

    def result(self, point: Point, solver_name: str, decay: bool = True) -> PointResult:
        """The summary of ``point`` run with ``solver_name`` (``decay``: also fit the decay rate)."""
        key = (point, solver_name, decay)
        if key not in self._cache:
            traj = run(point, solver_name, self.settings)
            self._cache[key] = summarize(traj, point, solver_name, self.settings, decay)
        return self._cache[key]
