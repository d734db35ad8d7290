"""A forced stick phase: the held force along it, its monotone pieces and where it leaves the static bound.

While the mass sticks from (ts, xs), X = xs + V_b (tau - ts) and X' = V_b,
so the force the interface must hold, F_e - f(tau) (:func:`~.friction.held_force`),
is an explicit function of tau (:func:`held_along`) with the rate
V_b - f'(tau).  The stick ends where it first reaches |F_e - f| >= F_s
moving outwards; an unforced stick has a closed form for that
(:func:`~.friction.stick_duration`), a forced one is searched here.

The rate's zeros are known in closed form (:func:`next_turn`), so the held
force is walked through its monotone pieces: on each it crosses a level iff
it is beyond it at the piece's end, and no excursion however short is
missed (:func:`exit_time`, :func:`friction_zero`).  Every kernel that
integrates Coulomb's stick rule through a forced stick ends it here: the
adaptive kernel (:mod:`.dopri`), the tangent integrator (:mod:`.tangent`)
and the forced map (:mod:`.forced_map`), whose stick phases are searched
once each, off their step grid.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .friction import FEX, OMEGA, PHI, external_force, held_force


@njit(cache=True)
def held_along(xs, ts, t, zeta, vb, res, p):
    """F_e - f(t), the force the interface must hold at ``t`` in a stick phase that began at (ts, xs).

    ``res``: F_e = X + 2 zeta V_b (else X); ``p``: the force record (its external force).
    """
    return held_force(xs + vb * (t - ts), zeta, vb, res, external_force(p, t))


@njit(cache=True)
def next_turn(t, vb, p):
    """The first time after ``t`` where the held force turns: its rate V_b - f' = V_b + F_ex Omega sin(Omega t + phi) vanishes.

    Between two turns it is monotone.  inf when it never turns (|V_b| >= F_ex Omega, unforced included).
    """
    om, ph = p[OMEGA], p[PHI]
    amp = p[FEX] * om
    if amp == 0.0:
        return np.inf
    r = -vb / amp
    if abs(r) >= 1.0:
        return np.inf
    two_pi = 2.0 * math.pi
    first = math.asin(r)
    best = np.inf
    for th in (first, math.pi - first):
        tc = (th + two_pi * (math.floor((om * t + ph - th) / two_pi) + 1.0) - ph) / om
        while tc <= t:  # rounding
            tc += two_pi / om
        best = min(best, tc)
    return best


@njit(cache=True)
def level_time(xs, ts, lo, hi, level, s, offset, zeta, vb, res, p):
    """Bisection on a monotone piece where s (held + offset) < level at lo and >= level at hi: the first time it is >= level."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if s * (held_along(xs, ts, mid, zeta, vb, res, p) + offset) >= level:
            hi = mid
        else:
            lo = mid
    return hi


@njit(cache=True)
def exit_time(xs, ts, t_end, hold, zeta, vb, fs, res, p):
    """When a forced stick from (ts, xs) first reaches |F_e - f| >= F_s moving outwards (t_end if never).

    The held force is walked through its monotone pieces (:func:`next_turn`):
    on each it leaves the bound iff it is beyond it at the piece's end, so an
    excursion however short is found, to the last bit by bisection.  With
    ``hold`` (it was on the bound and held there) the first piece does not
    end the stick if it starts on the bound already.  Unforced (F_ex = 0)
    the held force moves at V_b, one piece to ``t_end``: bisected like the
    others rather than taken from the closed form
    (:func:`~.friction.stick_duration`), whose rounding may leave the force
    the caller evaluates there a few units below F_s.
    """
    a = ts
    ga = held_along(xs, ts, a, zeta, vb, res, p)
    while a < t_end:
        b = min(next_turn(a, vb, p), t_end)
        gb = held_along(xs, ts, b, zeta, vb, res, p)
        s = 1.0 if gb >= ga else -1.0  # the held force's direction on the piece
        if s * gb >= fs:
            if s * ga < fs:
                return level_time(xs, ts, a, b, fs, s, 0.0, zeta, vb, res, p)
            if not (hold and a == ts):
                return a
        a, ga = b, gb
    return t_end


@njit(cache=True)
def friction_zero(xs, ts, t0, t1, zeta, vb, res, p):
    """The first sign change of the held friction force F_c = X + 2 zeta V_b - f in (t0, t1) (inf if none)."""
    off = 0.0 if res else 2.0 * zeta * vb  # F_c - (F_e - f)
    a = t0
    fa = held_along(xs, ts, a, zeta, vb, res, p) + off
    while a < t1:
        b = min(next_turn(a, vb, p), t1)
        fb = held_along(xs, ts, b, zeta, vb, res, p) + off
        if fa * fb < 0.0:
            s = 1.0 if fb > 0.0 else -1.0
            z = level_time(xs, ts, a, b, 0.0, s, off, zeta, vb, res, p)
            return z if z < t1 else np.inf
        a, fa = b, fb
    return np.inf
