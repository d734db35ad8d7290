"""Find the steady state of a run instead of assuming it.

Three outcomes:

``periodic``
    The maxima and minima of X on the section X' = 0 have repeated, with the
    same period, to within ``rtol`` for at least ``min_periods`` periods.  The
    window is the whole number of trailing periods that repeat, cut at the
    section.
``equilibrium``
    X and X' have stopped moving (spread below ``rtol`` over the tail).
``not_settled``
    Neither.  The amplitude's measured exponential rate (``decay_rate`` > 0:
    decaying, < 0: growing) and where the sequence is heading (Aitken
    extrapolation of the amplitudes and centres) are reported; the window is
    the last whole period, or the tail of the run.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from ..trajectory import Trajectory
from .sections import crossings

KINDS = ("periodic", "equilibrium", "not_settled")


@dataclass(frozen=True)
class SteadyState:
    """What the run settled on, and the window to average over."""

    kind: str
    window: tuple[float, float]
    period: float | None = None
    n_periods: int = 0
    decay_rate: float | None = None
    heading: str | None = None
    limit: dict[str, float] | None = None
    manual_window: bool = False
    stability: str | None = None
    stick_fraction: float | None = None

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["window"] = [float(self.window[0]), float(self.window[1])]
        return d


def _tail_start(t: np.ndarray) -> float:
    span = t[-1] - t[0]
    return t[-1] - min(span, max(0.1 * span, 4.0 * math.pi))


def _aitken(a: np.ndarray) -> float:
    """Limit of a geometrically converging sequence from its last three terms."""
    a0, a1, a2 = a[-3], a[-2], a[-1]
    den = a2 - 2.0 * a1 + a0
    if den == 0.0:
        return float(a2)
    return float(a2 - (a2 - a1) ** 2 / den)


def steady_state(
    traj: Trajectory,
    *,
    rtol: float = 1e-6,
    min_periods: int = 3,
    window: tuple[float, float] | None = None,
) -> SteadyState:
    """Classify the end of ``traj`` as periodic, equilibrium or not settled.

    Parameters
    ----------
    rtol:
        Convergence tolerance relative to the motion's scale
        max(range of X, range of X', |V_b|, F_d).
    min_periods:
        Number of consecutive repeated periods a periodic orbit needs.
    window:
        ``(t0, t1)`` to average over instead of the detected window; the kind
        is still the detected one.
    """
    found = _classify(traj, rtol, min_periods)
    if window is None:
        return found
    t0, t1 = float(window[0]), float(window[1])
    if not (traj.t[0] <= t0 < t1 <= traj.t[-1]):
        raise ValueError(f"window must satisfy {traj.t[0]:g} <= T0 < T1 <= {traj.t[-1]:g}, got {t0:g}:{t1:g}")
    return replace(found, window=(t0, t1), manual_window=True, stick_fraction=stick_fraction(traj, (t0, t1)))


def stick_fraction(traj: Trajectory, window: tuple[float, float]) -> float:
    """Share of the window spent in the stick mode (time-weighted over samples)."""
    i0, i1 = traj.index(window[0]), traj.index(window[1])
    if i1 <= i0:
        return float(traj.mode[i0] == 0)
    dt = np.diff(traj.t[i0 : i1 + 1])
    return float(np.sum(dt * (traj.mode[i0:i1] == 0)) / np.sum(dt))


def _classify(traj: Trajectory, rtol: float, min_periods: int) -> SteadyState:
    t, x, v = traj.t, traj.x, traj.v
    scale = max(float(np.ptp(x)), float(np.ptp(v)), abs(traj.vb), traj.friction.fd, 1e-300)
    tol = rtol * scale

    # Equilibrium: nothing moves any more over the tail.
    ts = _tail_start(t)
    tail = t >= ts
    if np.ptp(x[tail]) <= tol and np.ptp(v[tail]) <= tol:
        w = (float(ts), float(t[-1]))
        return SteadyState("equilibrium", w, limit={"x": float(x[-1]), "v": float(v[-1])}, stick_fraction=stick_fraction(traj, w))

    hi = crossings(t, x, v, -1)
    lo = crossings(t, x, v, +1)
    h = float(np.max(np.diff(t))) if len(t) > 1 else 0.0

    # Periodic: maxima, minima and periods all repeat over the last periods.
    n = min(len(hi.t), len(lo.t) + 1)
    if n >= min_periods + 1:
        xm, tm = hi.x, hi.t
        periods = np.diff(tm)
        last_p = periods[-1]
        tol_p = rtol * last_p + h * h
        m = 0  # number of trailing periods that repeat the last one
        while m < len(periods):
            j = len(periods) - 1 - m
            ok = abs(xm[j] - xm[-1]) <= tol and abs(periods[j] - last_p) <= tol_p
            if not ok:
                break
            m += 1
        lo_ok = len(lo.x) >= min_periods and np.ptp(lo.x[-min_periods:]) <= tol
        if m >= min_periods and lo_ok:
            w = (float(tm[-1 - m]), float(tm[-1]))
            return SteadyState(
                "periodic",
                w,
                period=float((tm[-1] - tm[-1 - m]) / m),
                n_periods=m,
                stick_fraction=stick_fraction(traj, w),
            )

    # Not settled: measure where it is going.
    decay = heading = limit = None
    if len(hi.t) >= 2:
        w = (float(hi.t[-2]), float(hi.t[-1]))
    else:
        w = (float(ts), float(t[-1]))
    k = min(len(hi.x), len(lo.x))
    if k >= 2:
        amp = 0.5 * (hi.x[-k:] - lo.x[-k:])
        cen = 0.5 * (hi.x[-k:] + lo.x[-k:])
        tk = hi.t[-k:]
        use = slice(max(0, k - 6), k)
        if np.all(amp[use] > 0):
            slope = np.polyfit(tk[use], np.log(amp[use]), 1)[0] if k > 2 else math.log(amp[-1] / amp[-2]) / (tk[-1] - tk[-2])
            decay = float(-slope)
        if k >= 3 and decay is not None:
            a_inf = _aitken(amp)
            c_inf = _aitken(cen)
            if decay < 0:
                heading = "growing"
                limit = None
            elif a_inf <= max(tol, 1e-3 * amp[-1]):
                heading = "equilibrium"
                limit = {"x": c_inf}
            else:
                heading = "periodic"
                limit = {"amplitude": a_inf, "x_center": c_inf}
    return SteadyState("not_settled", w, decay_rate=decay, heading=heading, limit=limit, stick_fraction=stick_fraction(traj, w))
