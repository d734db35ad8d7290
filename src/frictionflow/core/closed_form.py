"""Closed forms of one phase of constant-coefficient motion.

Between switches the belt oscillator obeys one of three linear laws:

``OSC``  X'' + 2 zeta X' + X = F   (slip, or Karnopp's saturated band)
``LIN``  X'' = 0                   (stick: X' constant)
``EXP``  X'' = -2 zeta X'          (Karnopp's band holding F_e = X)

From a state (x0, v0) the motion is known in closed form; so are the
critical points of any linear event function g = a X + b X' - c (which cut
[0, T] into intervals where g is monotone), the zeros of X', and the
integral of X'^2.  Everything here is a scalar function for the kernels.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

OSC, LIN, EXP = 0, 1, 2
# underdamped, critically damped, overdamped
UNDER, CRIT, OVER = 0, 1, 2


@njit(cache=True)
def coefficients(dyn, zeta, force, x0, v0):
    """Coefficients of the motion from (x0, v0): (regime, r1, r2, p, q).

    OSC underdamped: Y = X - F = e^{-zeta t}(p cos wt + q sin wt), r1 = zeta, r2 = w.
    OSC critical:    Y = e^{-t}(p + q t).
    OSC overdamped:  Y = p e^{r1 t} + q e^{r2 t}.
    LIN:             X = x0 + v0 t.
    EXP:             X' = v0 e^{-r1 t}, r1 = 2 zeta.
    """
    if dyn == OSC:
        y0 = x0 - force
        if zeta < 1.0:
            w = math.sqrt(1.0 - zeta * zeta)
            return UNDER, zeta, w, y0, (v0 + zeta * y0) / w
        if zeta == 1.0:
            return CRIT, 1.0, 1.0, y0, v0 + y0
        s = math.sqrt(zeta * zeta - 1.0)
        l1 = -zeta + s
        l2 = -zeta - s
        a = (v0 - l2 * y0) / (l1 - l2)
        return OVER, l1, l2, a, y0 - a
    if dyn == EXP:
        return UNDER, 2.0 * zeta, 0.0, x0, v0
    return UNDER, 0.0, 0.0, x0, v0


@njit(cache=True)
def state(dyn, zeta, force, x0, v0, t):
    """(X, X', X'') at time t after the phase starts at (x0, v0)."""
    return state_with(coefficients(dyn, zeta, force, x0, v0), dyn, zeta, force, x0, v0, t)


@njit(cache=True)
def state_with(co, dyn, zeta, force, x0, v0, t):
    """:func:`state` with the phase's :func:`coefficients` computed once by the caller."""
    if dyn == LIN:
        return x0 + v0 * t, v0, 0.0
    if dyn == EXP:
        c = 2.0 * zeta
        if c == 0.0:
            return x0 + v0 * t, v0, 0.0
        e = math.exp(-c * t)
        return x0 + v0 * (-math.expm1(-c * t)) / c, v0 * e, -c * v0 * e
    reg, r1, r2, p, q = co
    if reg == UNDER:
        e = math.exp(-r1 * t)
        cs = math.cos(r2 * t)
        sn = math.sin(r2 * t)
        y = e * (p * cs + q * sn)
        v = e * ((r2 * q - r1 * p) * cs - (r2 * p + r1 * q) * sn)
    elif reg == CRIT:
        e = math.exp(-t)
        y = e * (p + q * t)
        v = e * (q - p - q * t)
    else:
        e1 = math.exp(r1 * t)
        e2 = math.exp(r2 * t)
        y = p * e1 + q * e2
        v = r1 * p * e1 + r2 * q * e2
    return force + y, v, -y - 2.0 * zeta * v


@njit(cache=True)
def first_critical(co, dyn, a, b, t_from):
    """(t, step): the first time > ``t_from`` where g = a X + b X' has g' = 0, and the spacing of the next ones.

    ``co``: the phase's :func:`coefficients`.  OSC underdamped: g' = 0 every
    pi / w from t on; otherwise there is at most one such time (step = inf);
    t = inf when there is none.
    """
    if dyn != OSC:
        return np.inf, np.inf  # LIN: g linear in t; EXP: g = const + k e^{-ct}; both monotone
    reg, r1, r2, p, q = co
    if reg == UNDER:
        # g - const = e^{-r1 t}(P cos + Q sin); g' = e^{-r1 t}(P' cos + Q' sin)
        vc = r2 * q - r1 * p
        vs = -(r2 * p + r1 * q)
        P = a * p + b * vc
        Q = a * q + b * vs
        P1 = -r1 * P + r2 * Q
        Q1 = -r1 * Q - r2 * P
        if P1 == 0.0 and Q1 == 0.0:
            return np.inf, np.inf
        phi = math.atan2(Q1, P1)
        # zeros of cos(r2 t - phi): r2 t = phi + pi/2 + k pi
        t0 = (phi + 0.5 * math.pi) / r2
        step = math.pi / r2
        t = t0 + math.ceil((t_from - t0) / step) * step
        if t <= t_from:
            t += step
        return t, step
    t = np.inf
    if reg == CRIT:
        # g - const = e^{-t}(P + Q t)
        P = a * p + b * (q - p)
        Q = a * q - b * q
        if Q != 0.0:
            t = (Q - P) / Q
    else:
        P = (a + b * r1) * p
        Q = (a + b * r2) * q
        if P != 0.0 and Q != 0.0:
            ratio = -r2 * Q / (r1 * P)
            if ratio > 0.0:
                t = math.log(ratio) / (r1 - r2)
    return (t if t > t_from else np.inf), np.inf


@njit(cache=True)
def critical_points(co, dyn, a, b, t_from, t_max, out):
    """Times in (t_from, t_max) where g = a X + b X' has g' = 0, ascending; returns how many.

    ``co``: the phase's :func:`coefficients`.  For OSC underdamped the times
    repeat every pi / w; at most ``len(out)`` are returned (the caller asks
    again from the last one).
    """
    t, step = first_critical(co, dyn, a, b, t_from)
    n = 0
    while t < t_max and n < len(out):
        out[n] = t
        n += 1
        t += step
    return n


@njit(cache=True)
def envelope(co, dyn, zeta, a, b):
    """(A, r) with |g(s) - g(inf)| <= A e^{-r s} for all s (A = inf where there is no such bound)."""
    if dyn != OSC or zeta <= 0.0:
        return np.inf, 0.0
    reg, r1, r2, p, q = co
    if reg == UNDER:
        vc = r2 * q - r1 * p
        vs = -(r2 * p + r1 * q)
        return math.hypot(a * p + b * vc, a * q + b * vs), r1
    return np.inf, 0.0  # non-oscillating: at most two roots, found by bracketing


@njit(cache=True)
def integral_v2(dyn, zeta, force, x0, v0, T):
    """int_0^T X'^2 dt in closed form."""
    if dyn == LIN or (dyn == EXP and zeta == 0.0):
        return v0 * v0 * T
    if dyn == EXP:
        c = 2.0 * zeta
        return v0 * v0 * (-math.expm1(-2.0 * c * T)) / (2.0 * c)
    reg, r1, r2, p, q = coefficients(dyn, zeta, force, x0, v0)
    if reg == UNDER:
        C = r2 * q - r1 * p
        D = -(r2 * p + r1 * q)
        s = 0.5 * (C * C + D * D)
        dc = 0.5 * (C * C - D * D)
        ds = C * D
        al = -2.0 * r1
        be = 2.0 * r2
        i0 = -math.expm1(al * T) / (-al) if al != 0.0 else T
        e = math.exp(al * T)
        cb = math.cos(be * T)
        sb = math.sin(be * T)
        den = al * al + be * be
        ic = (e * (al * cb + be * sb) - al) / den
        is_ = (e * (al * sb - be * cb) + be) / den
        return s * i0 + dc * ic + ds * is_
    if reg == CRIT:
        C = q - p
        D = -q
        e = math.exp(-2.0 * T)
        i0 = -math.expm1(-2.0 * T) / 2.0
        i1 = (1.0 - e * (1.0 + 2.0 * T)) / 4.0
        i2 = (1.0 - e * (1.0 + 2.0 * T + 2.0 * T * T)) / 4.0
        return C * C * i0 + 2.0 * C * D * i1 + D * D * i2
    P = r1 * p
    Q = r2 * q
    return P * P * math.expm1(2 * r1 * T) / (2 * r1) + 2 * P * Q * math.expm1((r1 + r2) * T) / (r1 + r2) + Q * Q * math.expm1(2 * r2 * T) / (2 * r2)
