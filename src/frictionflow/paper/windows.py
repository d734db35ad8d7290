"""Averaging windows of whole cycles, and the paper's Eq. 6 and 9 evaluated over them.

A cycle runs from one maximum of X to the next (or minimum to minimum): the
samples where X' changes sign.  For a periodic motion any cycle gives the
same averages; for Case II's decaying spiral they depend on where the cycle
sits -- which is the point of :mod:`.transient`.

Averages are the trapezoidal quadrature of the instantaneous power over the
window's samples (summed per window with ``np.add.reduceat``, so that all
cycles of a run are evaluated at once), as the paper's time-averaging of its RK4 samples, rather
than differences of the solver's running work integrals
(:func:`~frictionflow.analysis.power_flow`): deep in Case II's decay one
cycle's damper work (about 2 pi zeta A^2, ~1e-20 at tau = 600 for
zeta = 0.03) is below the rounding of the running integral (~1e-16 times
the V_b^2 / 2 dissipated since tau = 0), so the difference would be noise.
Where both are meaningful they agree (see the tests).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..analysis import instantaneous_power
from ..trajectory import Trajectory

#: where a cycle starts: at the maxima or at the minima of X
CYCLE_STARTS = ("max", "min")


@dataclass(frozen=True)
class WindowAverages:
    """Eq. 9 and Eq. 6 over one window.

    ``R_c``/``R_f`` are NaN when friction puts in nothing (P_fin = 0).
    ``amplitude`` is half the range of X over the window; ``dE`` the mean
    rate of change of K + U, so that P_fin - P_df - P_dv = dE up to quadrature
    error.
    """

    t0: float
    t1: float
    P_dv: float
    P_fin: float
    P_df: float
    R_c: float
    R_f: float
    TR_B: float
    amplitude: float
    dE: float

    @property
    def net_friction(self) -> float:
        """P_fin - P_df: the friction's net power input (the mean of X' F_c)."""
        return self.P_fin - self.P_df


def tail(traj: Trajectory, t_from: float) -> Trajectory:
    """The part of ``traj`` from ``t_from`` on (views, not copies): windows at the end need no more."""
    i = traj.index(t_from)
    dwork = traj.dwork[i:].copy()
    dwork[0] = 0.0  # the integrals before t_from are not part of the tail
    return replace(traj, t=traj.t[i:], state=traj.state[:, i:], force=traj.force[:, i:], modes=traj.modes[:, i:],
                   dwork=dwork)


class Cycles:
    """The cycles of one trajectory and averages over them (power computed once)."""

    def __init__(self, traj: Trajectory) -> None:
        self.traj = traj
        p = instantaneous_power(traj)
        self.p_dv = p["P_dv"]
        self.p_in = np.maximum(p["P_f"], 0.0)
        self.p_out = np.maximum(-p["P_f"], 0.0)
        self.f_tb = np.abs(traj.transmitted_force)
        self._starts: dict[str, np.ndarray] = {}

    def starts(self, at: str = "max") -> np.ndarray:
        """Indices of the first sample at or after each maximum (``max``) or minimum (``min``) of X."""
        if at not in CYCLE_STARTS:
            raise ValueError(f"at must be one of {', '.join(CYCLE_STARTS)}, got {at!r}")
        if at not in self._starts:
            v = self.traj.v
            if at == "max":
                hit = (v[:-1] > 0.0) & (v[1:] <= 0.0)
            else:
                hit = (v[:-1] < 0.0) & (v[1:] >= 0.0)
            self._starts[at] = np.flatnonzero(hit) + 1
        return self._starts[at]

    def last_cycle(self, t_end: float | None = None, at: str = "max") -> tuple[int, int]:
        """The last whole cycle ending at or before ``t_end``; at rest, the last 2 pi."""
        t = self.traj.t
        t_end = float(t[-1]) if t_end is None else t_end
        s = self.starts(at)
        s = s[t[s] <= t_end + 1e-12]
        if len(s) >= 2:
            return int(s[-2]), int(s[-1])
        i1 = self.traj.index(t_end)
        return self.traj.index(t[i1] - 2.0 * math.pi), i1

    def averages(self, bounds: np.ndarray) -> dict[str, np.ndarray]:
        """Eq. 9 (and TR_B, Eq. 6) over the consecutive windows ``bounds[k]..bounds[k+1]`` (sample indices).

        Vectorised over windows: each integral is a sum of trapezoids within
        its window, never a difference of running sums.
        """
        b = np.asarray(bounds, dtype=np.int64)
        if len(b) < 2 or np.any(np.diff(b) <= 0):
            raise ValueError(f"windows need increasing sample indices, at least two; got {b[:5]}...")
        tr = self.traj
        lo, hi = b[:-1], b[1:]
        t = tr.t
        dt = np.diff(t[b[0] : b[-1] + 1])
        span = t[hi] - t[lo]
        rel = b - b[0]

        def mean(q: np.ndarray) -> np.ndarray:
            seg = 0.5 * (q[b[0] : b[-1]] + q[b[0] + 1 : b[-1] + 1]) * dt
            return np.add.reduceat(seg, rel[:-1]) / span

        def extreme(q: np.ndarray, ufunc) -> np.ndarray:
            inner = ufunc.reduceat(q[b[0] : b[-1]], rel[:-1])
            return ufunc(inner, q[hi])  # the window's last sample counts too

        p_dv, p_in, p_out = mean(self.p_dv), mean(self.p_in), mean(self.p_out)
        with np.errstate(divide="ignore", invalid="ignore"):
            r_c = np.where(p_in > 0.0, p_dv / p_in, np.nan)
            r_f = np.where(p_in > 0.0, p_out / p_in, np.nan)
        fd = tr.friction.fd
        energy = 0.5 * (tr.v[b] ** 2 + tr.x[b] ** 2)
        return {
            "t0": t[lo],
            "t1": t[hi],
            "P_dv": p_dv,
            "P_fin": p_in,
            "P_df": p_out,
            "R_c": r_c,
            "R_f": r_f,
            "TR_B": extreme(self.f_tb, np.maximum) / fd if fd > 0 else np.full(len(lo), np.nan),
            "amplitude": 0.5 * (extreme(tr.x, np.maximum) - extreme(tr.x, np.minimum)),
            "dE": np.diff(energy) / span,
            "net_friction": p_in - p_out,
            "peak_P_dv": extreme(self.p_dv, np.maximum),
            "peak_P_f": extreme(np.maximum(self.p_in, self.p_out), np.maximum),
        }

    def average(self, i0: int, i1: int) -> WindowAverages:
        """Eq. 9 (and TR_B, Eq. 6) over samples ``i0..i1``."""
        if i1 <= i0:
            raise ValueError(f"a window needs at least two samples, got {i0}..{i1}")
        a = self.averages(np.array([i0, i1]))
        return WindowAverages(**{f: float(a[f][0]) for f in WindowAverages.__dataclass_fields__})

    def peaks(self, i0: int, i1: int) -> dict[str, float]:
        """Largest instantaneous damper power and largest |P_f| over samples ``i0..i1`` (Fig. 4's scales)."""
        sl = slice(i0, i1 + 1)
        return {"P_dv": float(self.p_dv[sl].max()), "P_f": float(np.maximum(self.p_in[sl], self.p_out[sl]).max())}
