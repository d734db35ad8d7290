"""Extremes and threshold shares between a run's samples, on the cubic Hermite interpolant.

A solver whose samples need not hold the turns of X' (the stiff solver: its steps end on the zeros of X' and
P_f, not of X'') leaves V's extremes, the transmitted force's and a threshold-defined stick's boundary between
samples, where the sampled values miss them by O(h^2) (a stick share by O(h)).  Each sample carries the state's
derivative (X'' from the equation of motion), so between two samples the cubic Hermite interpolant of a quantity
and its rate is fourth-order accurate for a smooth law; its extremes and crossings are found here in closed form
(the interpolant's critical points) and by the roots of its cubic.  A law whose force jumps at a switch (Coulomb
stick to slip) has no smooth rate there: these functions are for the runs whose solver declares them
(``Solver.refine_between_samples``).
"""

from __future__ import annotations

import numpy as np

from ..solvers.registry import solver_named
from ..trajectory import Trajectory

__all__ = ["hermite_extremes", "share_below", "refines", "velocity_extremes", "force_peak", "stick_share"]


def _cubic(t: np.ndarray, y: np.ndarray, dy: np.ndarray) -> tuple[np.ndarray, ...]:
    """Per step, the coefficients of p(s) = c0 + c1 s + c2 s^2 + c3 s^3 on s in [0, 1] through (y, dy h)."""
    h = np.diff(t)
    y0, y1, m0, m1 = y[:-1], y[1:], dy[:-1] * h, dy[1:] * h
    return y0, m0, 3.0 * (y1 - y0) - 2.0 * m0 - m1, 2.0 * (y0 - y1) + m0 + m1


def _critical_values(c: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Per step, the interpolant's least and largest value at its critical points inside (0, 1) (+inf / -inf
    where there are none): the roots of p'(s) = c1 + 2 c2 s + 3 c3 s^2, by the cancellation-free formula."""
    c0, c1, c2, c3 = c
    a, b = 3.0 * c3, 2.0 * c2
    disc = b * b - 4.0 * a * c1
    root = np.sqrt(np.where(disc >= 0.0, disc, 0.0))
    q = -0.5 * (b + np.where(b >= 0.0, root, -root))
    lo, hi = np.full(len(c0), np.inf), np.full(len(c0), -np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for s in (q / a, c1 / q):
            ok = (disc >= 0.0) & np.isfinite(s) & (s > 0.0) & (s < 1.0)
            p = c0 + s * (c1 + s * (c2 + s * c3))
            lo, hi = np.where(ok, np.minimum(lo, p), lo), np.where(ok, np.maximum(hi, p), hi)
    return lo, hi


def hermite_extremes(t: np.ndarray, y: np.ndarray, dy: np.ndarray) -> tuple[float, float]:
    """The least and largest value of the cubic Hermite interpolant of ``y`` with rate ``dy`` at times ``t``."""
    if len(t) < 2:
        return float(np.min(y)), float(np.max(y))
    lo, hi = _critical_values(_cubic(t, y, dy))
    return float(min(np.min(y), np.min(lo))), float(max(np.max(y), np.max(hi)))


def share_below(t: np.ndarray, y: np.ndarray, dy: np.ndarray, level: float) -> float:
    """The share of [t[0], t[-1]] where |p| < ``level`` for the cubic Hermite interpolant p of ``y``, ``dy``.

    Steps whose interpolant stays on one side count whole; on the others (it reaches +-level) the crossings are
    the real roots in (0, 1) of p(s) -+ level, and each piece between them is in or out by its midpoint.
    """
    span = float(t[-1] - t[0]) if len(t) > 1 else 0.0
    if span <= 0.0:
        return float(abs(y[0]) < level)
    c = _cubic(t, y, dy)
    lo, hi = _critical_values(c)
    lo, hi = np.minimum(np.minimum(y[:-1], y[1:]), lo), np.maximum(np.maximum(y[:-1], y[1:]), hi)
    h = np.diff(t)
    inside = np.abs(0.5 * (y[:-1] + y[1:])) < level  # a step wholly on one side: where its ends are
    mixed = np.nonzero(((lo < level) & (hi > level)) | ((lo < -level) & (hi > -level)))[0]
    total = float(np.sum(h[inside]) - np.sum(h[mixed][inside[mixed]]))
    for i in mixed:
        total += h[i] * _inside_length([c[0][i], c[1][i], c[2][i], c[3][i]], level)
    return total / span


def _inside_length(c: list[float], level: float) -> float:
    """The length of s in [0, 1] where |c0 + c1 s + c2 s^2 + c3 s^3| < level."""
    cuts = [0.0, 1.0]
    for shift in (level, -level):
        for r in np.roots([c[3], c[2], c[1], c[0] - shift]):
            if abs(r.imag) <= 1e-12 * max(1.0, abs(r.real)) and 0.0 < r.real < 1.0:
                cuts.append(float(r.real))
    cuts.sort()
    length = 0.0
    for a, b in zip(cuts[:-1], cuts[1:]):
        m = 0.5 * (a + b)
        if abs(c[0] + m * (c[1] + m * (c[2] + m * c[3]))) < level:
            length += b - a
    return length


# -- a run's quantities ---------------------------------------------------------------------------------------

def refines(traj: Trajectory) -> bool:
    """Does ``traj``'s solver leave these points between its samples (``Solver.refine_between_samples``)?"""
    cls = solver_named(traj.solver.get("name"))
    return cls is not None and cls.refine_between_samples


def velocity_extremes(traj: Trajectory, s: slice) -> tuple[float, float]:
    """(V_min, V_max) over the samples ``s`` and between them (X'' is X''s rate)."""
    return hermite_extremes(traj.t[s], traj.v[s], traj.acceleration[s])


def force_peak(traj: Trajectory, s: slice) -> float:
    """max |F_T| = max |X + 2 zeta X'| over the samples ``s`` and between them."""
    lo, hi = hermite_extremes(traj.t[s], traj.transmitted_force[s],
                              traj.v[s] + 2.0 * traj.zeta * traj.acceleration[s])
    return max(hi, -lo)


def stick_share(traj: Trajectory, s: slice) -> float:
    """The share of the samples ``s``'s span where |V_r| is below the law's stick speed, crossings included."""
    t = traj.t[s]
    vr = traj.model.belt_speed(t) - traj.v[s]
    dvr = traj.model.belt_accel(t) - traj.acceleration[s]
    return share_below(t, vr, dvr, traj.friction.stick_speed())
