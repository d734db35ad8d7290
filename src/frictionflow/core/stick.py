"""A forced stick phase: the held force along it, its monotone pieces and where it leaves the static bound.

While the mass sticks from (ts, xs), X' = V_b(tau) and X = xs + int V_b
(:func:`stick_x`; xs + V_b (tau - ts) on a belt at constant speed), so the
force the interface must hold, F_e + V_b' - f(tau) (:func:`~.friction.held_force`
with the load :func:`~.friction.stick_load`), is an explicit function of tau
(:func:`held_along`), with the rate V_b - f'(tau) on a constant belt.  The
stick ends where it first reaches |F_e + V_b' - f| >= F_s moving outwards;
an unforced stick on a constant belt has a closed form for that
(:func:`~.friction.stick_duration`), the others are searched here.

The rate's zeros are known in closed form (:func:`next_turn`), so the held
force is walked through its monotone pieces: on each it crosses a level iff
it is beyond it at the piece's end, and no excursion however short is
missed (:func:`exit_time`, :func:`friction_zero`).  A belt whose speed
varies adds a sinusoid of its own to the rate; with two frequencies its
zeros have no closed form, and the pieces are walked in steps that a bound
on the rate's second derivative proves free of them (:func:`belt_turn`).
Every kernel that integrates Coulomb's stick rule through a forced stick
ends it here: the adaptive kernel (:mod:`.dopri`), the tangent integrator
(:mod:`.tangent`) and the forced map (:mod:`.forced_map`), whose stick
phases are searched once each, off their step grid.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .friction import (FEX, OMEGA, PHI, VB_AMP, VB_OMEGA, VB_PHI, belt_accel, belt_speed, external_force, held_force,
                       stick_friction, stick_load)

#: Gauss-Legendre's 8 nodes and weights on [-1, 1], for the works of a stick phase on a moving belt
GL_X, GL_W = np.polynomial.legendre.leggauss(8)
#: a sub-interval of that quadrature spans at most this many radians of the fastest oscillation (error ~ 0.5^17 / 16!)
GL_SPAN = 0.5


@njit(cache=True)
def stick_x(xs, ts, t, vb, p):
    """X at ``t`` in a stick phase from (ts, xs): xs + int_ts^t V_b, closed form.

    On a moving belt xs + V_b (t - ts) - (A/Omega_b)(cos(Omega_b t + phi_b) - cos(Omega_b ts + phi_b)),
    the difference of cosines as a product (no cancellation); xs + V_b (t - ts) on a constant one.
    """
    amp = p[VB_AMP]
    if amp == 0.0:
        return xs + vb * (t - ts)
    om = p[VB_OMEGA]
    return xs + vb * (t - ts) + 2.0 * amp / om * math.sin(om * 0.5 * (t + ts) + p[VB_PHI]) * math.sin(0.5 * om * (t - ts))


@njit(cache=True)
def held_along(xs, ts, t, zeta, vb, res, p):
    """F_e + V_b' - f(t), the force the interface must hold at ``t`` in a stick phase that began at (ts, xs).

    ``res``: F_e = X + 2 zeta V_b(t) (else X); ``p``: the force record (its external force and its belt).
    """
    return held_force(stick_x(xs, ts, t, vb, p), zeta, belt_speed(p, vb, t), res, stick_load(p, t))


@njit(cache=True)
def stick_force_along(xs, ts, t, zeta, vb, p):
    """F_c = X + 2 zeta V_b + V_b' - f at ``t`` in a stick phase that began at (ts, xs)."""
    return stick_friction(stick_x(xs, ts, t, vb, p), zeta, belt_speed(p, vb, t), stick_load(p, t))


@njit(cache=True)
def sine_root(t, c, amp, om, ph):
    """The first time after ``t`` where c + amp sin(om t + ph) vanishes changing sign (inf if it never does)."""
    if amp == 0.0:
        return np.inf
    r = -c / amp
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
def next_turn(t, vb, p):
    """The first time after ``t`` where the held force turns: its rate V_b - f' = V_b + F_ex Omega sin(Omega t + phi) vanishes.

    Between two turns it is monotone.  inf when it never turns (|V_b| >= F_ex Omega, unforced included).
    """
    return sine_root(t, vb, p[FEX] * p[OMEGA], p[OMEGA], p[PHI])


@njit(cache=True)
def belt_zero(t, vb, p):
    """The first time after ``t`` where the belt's speed V_b(tau) changes sign (inf if it never does)."""
    return sine_root(t, vb, p[VB_AMP], p[VB_OMEGA], p[VB_PHI])


@njit(cache=True)
def _rates(t, vb, zeta, dmp, p):
    """On a moving belt: the rate and second rate at ``t`` of S = X + [dmp] 2 zeta V_b + V_b' - f along a stick, and
    a bound on the third anywhere.

    dS/dtau = V_b + A (1 - Omega_b^2) sin(th_b) + [dmp] 2 zeta A Omega_b cos(th_b) + F_ex Omega sin(th_f).
    """
    amp, om = p[VB_AMP], p[VB_OMEGA]
    cs = amp * (1.0 - om * om)
    cc = 2.0 * zeta * om * amp if dmp else 0.0
    thb = om * t + p[VB_PHI]
    sb, cb = math.sin(thb), math.cos(thb)
    fa, wf = p[FEX] * p[OMEGA], p[OMEGA]
    thf = wf * t + p[PHI]
    r1 = vb + cs * sb + cc * cb + fa * math.sin(thf)
    r2 = om * (cs * cb - cc * sb) + fa * wf * math.cos(thf)
    m3 = om * om * math.hypot(cs, cc) + abs(fa) * wf * wf
    return r1, r2, m3


@njit(cache=True)
def belt_turn(t, t_max, vb, zeta, dmp, p):
    """On a moving belt, a time after ``t`` up to which S (:func:`_rates`) is monotone: its first turn (to
    rounding), or ``t_max``.

    From a, the rate S1 keeps its sign s while s S1(a) + s S2(a) d - M3 d^2 / 2 > 0 (S2 the second rate, M3 the
    bound on the third): each step goes to that bound's root, which closes in on a simple zero quadratically.
    A step below rounding ends the piece there: a piece that ends short of a turn only adds a piece, and S
    changes by rounding over such a step.
    """
    a = t
    for _ in range(100000):
        r1, r2, m3 = _rates(a, vb, zeta, dmp, p)
        if m3 == 0.0:
            return t_max  # a constant rate: no turn
        g = abs(r1)
        q = (r2 if r1 > 0.0 else -r2) if r1 != 0.0 else abs(r2)
        disc = math.sqrt(q * q + 2.0 * m3 * g)
        d = (q + disc) / m3 if q > 0.0 else (2.0 * g / (disc - q) if disc - q > 0.0 else 0.0)
        floor = 1e-13 * (1.0 + abs(a))
        if d <= floor:
            return min(a + floor, t_max)
        a += d
        if a >= t_max:
            return t_max
    return min(a, t_max)


@njit(cache=True)
def turn_after(t, t_max, vb, zeta, dmp, p):
    """The end (up to ``t_max``) of the monotone piece from ``t`` of the held force along a stick, with the damper's
    term if ``dmp``: :func:`next_turn` on a constant belt, :func:`belt_turn` on a moving one."""
    if p[VB_AMP] == 0.0:
        return min(next_turn(t, vb, p), t_max)
    return belt_turn(t, t_max, vb, zeta, dmp, p)


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
    """When a forced stick from (ts, xs) first reaches |F_e + V_b' - f| >= F_s moving outwards (t_end if never).

    The held force is walked through its monotone pieces (:func:`turn_after`):
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
        b = turn_after(a, t_end, vb, zeta, res, p)
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
    """The first sign change of the held friction force F_c = X + 2 zeta V_b + V_b' - f in (t0, t1) (inf if none)."""
    # F_c is the held force with the damper's term: on a constant belt F_e - f and an offset (2 zeta V_b when F_e = X),
    # walked through F_e - f's pieces; on a moving belt the damper's term varies, so F_c's own pieces (dmp)
    dmp = res or p[VB_AMP] != 0.0
    off = 0.0 if dmp else 2.0 * zeta * vb  # F_c - (F_e - f)
    a = t0
    fa = held_along(xs, ts, a, zeta, vb, dmp, p) + off
    while a < t1:
        b = turn_after(a, t1, vb, zeta, dmp, p)
        fb = held_along(xs, ts, b, zeta, vb, dmp, p) + off
        if fa * fb < 0.0:
            s = 1.0 if fb > 0.0 else -1.0
            z = level_time(xs, ts, a, b, 0.0, s, off, zeta, vb, dmp, p)
            return z if z < t1 else np.inf
        a, fa = b, fb
    return np.inf


@njit(cache=True)
def belt_stick_work(xs, ts, ta, tb, zeta, vb, p):
    """The works of stick over [ta, tb] on a moving belt: (int 2 zeta V_b^2, int V_b F_c, int V_b f).

    X' = V_b(tau) and F_c = :func:`stick_force_along`: products of sinusoids of two frequencies, integrated by
    composite Gauss-Legendre on sub-intervals spanning at most ``GL_SPAN`` radians of the fastest (to rounding).
    """
    fast = 1.0 + p[VB_OMEGA] + max(p[VB_OMEGA], p[OMEGA] if p[FEX] != 0.0 else 0.0)
    n = max(1, int(math.ceil((tb - ta) * fast / GL_SPAN)))
    h = (tb - ta) / n
    dv = pf = ex = 0.0
    for i in range(n):
        for j in range(len(GL_X)):
            t = ta + h * (i + 0.5 + 0.5 * GL_X[j])
            wgt = 0.5 * h * GL_W[j]
            v = belt_speed(p, vb, t)
            f = external_force(p, t)
            fc = stick_friction(stick_x(xs, ts, t, vb, p), zeta, v, f - belt_accel(p, t))
            dv += wgt * 2.0 * zeta * v * v
            pf += wgt * v * fc
            ex += wgt * v * f
    return dv, pf, ex
