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

import cmath
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
    return integral_v2_with(coefficients(dyn, zeta, force, x0, v0), T)


@njit(cache=True)
def integral_v2_with(co, T):
    """int_0^T Y'^2 dt of an OSC motion with :func:`coefficients` ``co`` (:func:`integral_v2`)."""
    reg, r1, r2, p, q = co
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


@njit(cache=True, forceinline=True)
def modulus(z):
    """|z| without hypot's overflow guard (a library call, slower than the arithmetic here): moderate values only."""
    return math.sqrt(z.real * z.real + z.imag * z.imag)


@njit(cache=True, forceinline=True)
def reciprocal(z):
    """1 / z as conj(z) / |z|^2 (no library division; z of moderate size, not 0)."""
    return z.conjugate() * (1.0 / (z.real * z.real + z.imag * z.imag))


# -- harmonic forcing -----------------------------------------------------------------------------
# Under f = Re(fz e^{i Omega t}) (t from the phase start, fz = F_ex e^{i theta}) the OSC motion is
# X = F + Y + Re(pz e^{i Omega t}): Y free (as above, from Y(0), Y'(0)) and the harmonic particular
# solution pz = H fz, H = 1 / (1 - Omega^2 + 2 i zeta Omega): amplitude F_ex / sqrt((1 - Omega^2)^2 +
# (2 zeta Omega)^2), phase lag atan2(2 zeta Omega, 1 - Omega^2).  LIN and EXP motions do not feel f
# (the interface holds it).  A phase is (co, pz, fz) with co as from :func:`coefficients`.

@njit(cache=True)
def forced_phase(dyn, zeta, force, x0, v0, fex, omega, theta):
    """(co, pz, fz) of a phase from (x0, v0) under F_ex cos(Omega t + theta).

    co: the free part's :func:`coefficients` (OSC: of Y = X - F - X_p; LIN,
    EXP: of X itself, as unforced).  pz: the particular solution's phasor
    (0 for LIN, EXP).  Undamped resonance (zeta = 0, Omega = 1) has no
    periodic particular solution: callers refuse it.
    """
    fz = fex * complex(math.cos(theta), math.sin(theta))
    if dyn != OSC:
        return coefficients(dyn, zeta, force, x0, v0), 0j, fz
    pz = fz * reciprocal(complex(1.0 - omega * omega, 2.0 * zeta * omega))
    # X_p(0) = Re pz, X_p'(0) = Re(i Omega pz) = -Omega Im pz
    return coefficients(OSC, zeta, force + pz.real, x0, v0 + omega * pz.imag), pz, fz


@njit(cache=True)
def free_motion(co, dyn, zeta, t):
    """The free part at t: (Y, Y', Y'', Y''', e1, e2); e1, e2: the exponentials it decays with.

    OSC: Y = X - F - X_p; LIN: X = x0 + v0 t; EXP: X' = v0 e^{-2 zeta t}.  e1
    (and e2 for overdamped OSC) feed :func:`free_bound`.
    """
    y, v, a, j, e1, e2, _ = _free_motion_exp(co, dyn, zeta, t)
    return y, v, a, j, e1, e2


@njit(cache=True)
def _free_motion_exp(co, dyn, zeta, t):
    """:func:`free_motion` and e^{lam t} (:func:`phase_exps`; 0 for OSC critically or over-damped)."""
    reg, r1, r2, p, q = co
    if dyn == LIN or (dyn == EXP and r1 == 0.0):
        return p + q * t, q, 0.0, 0.0, 1.0, 0.0, 1.0 + 0j
    if dyn == EXP:
        e = math.exp(-r1 * t)
        v = q * e
        return p + q * (-math.expm1(-r1 * t)) / r1, v, -r1 * v, r1 * r1 * v, e, 0.0, complex(e, 0.0)
    e2 = 0.0
    el = 0j
    if reg == UNDER:
        e1 = math.exp(-r1 * t)
        cs = math.cos(r2 * t)
        sn = math.sin(r2 * t)
        el = complex(e1 * cs, e1 * sn)
        y = e1 * (p * cs + q * sn)
        v = e1 * ((r2 * q - r1 * p) * cs - (r2 * p + r1 * q) * sn)
    elif reg == CRIT:
        e1 = math.exp(-t)
        y = e1 * (p + q * t)
        v = e1 * (q - p - q * t)
    else:
        e1 = math.exp(r1 * t)
        e2 = math.exp(r2 * t)
        y = p * e1 + q * e2
        v = r1 * p * e1 + r2 * q * e2
    a = -y - 2.0 * zeta * v
    return y, v, a, -v - 2.0 * zeta * a, e1, e2, el


@njit(cache=True)
def forced_state(co, dyn, zeta, force, pz, fz, omega, t):
    """(X, X', X'', X''', f, f', e1, e2) at t of a forced phase (:func:`forced_phase`)."""
    x, v, a, j, f, df, e1, e2, _, _ = forced_eval(co, dyn, zeta, force, pz, fz, omega, t)
    return x, v, a, j, f, df, e1, e2


@njit(cache=True)
def forced_eval(co, dyn, zeta, force, pz, fz, omega, t):
    """:func:`forced_state` and the exponentials of :func:`phase_exps` at t: (X, X', X'', X''', f, f', e1, e2, el, eo).

    One exp and two cos-sin pairs give the motion and, through el = e^{lam t}
    and eo = e^{i Omega t}, its work integrals (:func:`work_between`).
    """
    y, v, a, j, e1, e2, el = _free_motion_exp(co, dyn, zeta, t)
    c = math.cos(omega * t)
    s = math.sin(omega * t)
    eo = complex(c, s)
    f = fz.real * c - fz.imag * s
    df = -omega * (fz.imag * c + fz.real * s)
    if dyn != OSC:
        return y, v, a, j, f, df, e1, e2, el, eo
    xp = pz.real * c - pz.imag * s
    vp = -omega * (pz.imag * c + pz.real * s)
    w2 = omega * omega
    return force + y + xp, v + vp, a - w2 * xp, j - w2 * vp, f, df, e1, e2, el, eo


@njit(cache=True)
def free_bound(co, dyn, zeta, a, b, d):
    """Constants (K1, K2) of the bound on the free part of (a X + b X' + d X'')'' (see :func:`bound_at`)."""
    reg, r1, r2, p, q = co
    if dyn == LIN or (dyn == EXP and r1 == 0.0):
        return 0.0, 0.0
    if dyn == EXP:  # X^(k) = v0 (-c)^(k-1) e^{-ct}
        return abs(q) * abs(-a * r1 + b * r1 * r1 - d * r1 * r1 * r1), 0.0
    if reg == UNDER:  # Y = Re(C e^{lam t}), C = p - i q, lam = -r1 + i r2, |lam| = 1
        lam = complex(-r1, r2)
        return math.sqrt(p * p + q * q) * modulus(lam * lam * (a + lam * (b + d * lam))), 0.0
    if reg == CRIT:  # (..)'' = e^{-t}(A + B t): the constants A, B themselves
        k = a - b + d
        return k * p - q * (2.0 * a - 3.0 * b + 4.0 * d), k * q
    return (abs(p) * r1 * r1 * abs(a + r1 * (b + d * r1)), abs(q) * r2 * r2 * abs(a + r2 * (b + d * r2)))


@njit(cache=True)
def bound_at(co, dyn, K1, K2, Kp, t, e1, e2):
    """An upper bound of |G''| on [t, inf) for G = a X + b X' + d X'' - e f - c.

    (K1, K2) from :func:`free_bound`, e1, e2 from :func:`free_motion` at t;
    ``Kp`` bounds the harmonic part (Omega^2 times its amplitude).  The free
    part decays (zeta > 0) or keeps its amplitude (zeta = 0): its bound at t
    holds for all later times.
    """
    if dyn == OSC and co[0] == CRIT:
        al = abs(K1 + K2 * t)
        kb = abs(K2)
        free = e1 * al if kb <= al else e1 * kb * math.exp(al / kb - 1.0)
    else:
        free = K1 * e1 + K2 * e2
    return (free + Kp) * (1.0 + 1e-9) + 1e-300


@njit(cache=True)
def exp_integral(z, L):
    """int_0^L e^{z t} dt for complex z (a series where z L is small: no cancellation)."""
    return exp_integral_with(z, L, cmath.exp(z * L))


@njit(cache=True)
def exp_integral_with(z, L, ezl):
    """:func:`exp_integral` given e^{z L} (``ezl``, used where z L is not small)."""
    zl = z * L
    if abs(zl) >= 0.5:
        return (ezl - 1.0) / z
    s = 0j
    for n in range(18, -1, -1):  # L sum (zL)^n / (n + 1)!
        s = 1.0 + s * zl / (n + 2.0)
    return L * s


@njit(cache=True)
def texp_integral(z, L):
    """int_0^L t e^{z t} dt for complex z."""
    zl = z * L
    if abs(zl) >= 0.5:
        return (cmath.exp(zl) * (zl - 1.0) + 1.0) / (z * z)
    s = 0j
    term = 1.0 + 0j
    for n in range(24):  # L^2 sum (zL)^n / (n! (n + 2))
        s += term / (n + 2.0)
        term = term * zl / (n + 1.0)
    return L * L * s


@njit(cache=True)
def free_velocity_transform(co, dyn, zeta, omega, L):
    """J = int_0^L Y'(t) e^{i Omega t} dt of the free part of an OSC phase."""
    reg, r1, r2, p, q = co
    iw = complex(0.0, omega)
    if reg == UNDER:  # Y' = Re(C lam e^{lam t}) = (C lam e^{lam t} + conj(C lam) e^{conj(lam) t}) / 2
        lam = complex(-r1, r2)
        cl = complex(p, -q) * lam
        return 0.5 * (cl * exp_integral(lam + iw, L) + cl.conjugate() * exp_integral(lam.conjugate() + iw, L))
    if reg == CRIT:  # Y' = e^{-t}(q - p - q t)
        z = complex(-1.0, omega)
        return (q - p) * exp_integral(z, L) - q * texp_integral(z, L)
    return r1 * p * exp_integral(complex(r1, omega), L) + r2 * q * exp_integral(complex(r2, omega), L)


@njit(cache=True)
def forced_work(co, dyn, zeta, force, pz, fz, omega, L):
    """(int_0^L X'^2 dt, int_0^L X' f dt) of a forced phase, in closed form.

    OSC: X' = Y' + Re(i Omega pz e^{i Omega t}); the products of two harmonics
    Re(A e^{i W t}) Re(B e^{i W t}) = (Re(A B e^{2 i W t}) + Re(A conj B)) / 2.
    """
    reg, r1, r2, p, q = co
    if dyn == LIN or (dyn == EXP and r1 == 0.0):
        return q * q * L, q * (fz * exp_integral(complex(0.0, omega), L)).real
    if dyn == EXP:
        v2 = q * q * (-math.expm1(-2.0 * r1 * L)) / (2.0 * r1)
        return v2, q * (fz * exp_integral(complex(-r1, omega), L)).real
    rot = complex(math.cos(omega * L), math.sin(omega * L))  # e^{i Omega L}
    if reg == UNDER:
        J, y2 = _under_transforms(co, omega, L, rot)
    else:
        J, y2 = free_velocity_transform(co, dyn, zeta, omega, L), integral_v2_with(co, L)
    vz = complex(0.0, omega) * pz  # X_p' = Re(vz e^{i Omega t})
    i2 = exp_integral_with(complex(0.0, 2.0 * omega), L, rot * rot)
    vp2 = 0.5 * ((vz * vz * i2).real + L * (vz * vz.conjugate()).real)
    vpf = 0.5 * ((vz * fz * i2).real + L * (vz * fz.conjugate()).real)
    return y2 + 2.0 * (vz * J).real + vp2, (fz * J).real + vpf


@njit(cache=True)
def _under_transforms(co, omega, L, rot):
    """Underdamped OSC: (J, int_0^L Y'^2) of :func:`forced_work` from one exp, cos and sin (and e^{i Omega L} = ``rot``).

    The same sums as :func:`free_velocity_transform` and :func:`integral_v2_with`,
    with e^{(lam +- ...)L} composed from e^{-zeta L}, e^{i w L} and e^{i Omega L}.
    """
    _, r1, r2, p, q = co
    e = math.exp(-r1 * L)
    cw = math.cos(r2 * L)
    sw = math.sin(r2 * L)
    lam = complex(-r1, r2)
    iw = complex(0.0, omega)
    cl = complex(p, -q) * lam
    ew = e * complex(cw, sw)
    J = 0.5 * (cl * exp_integral_with(lam + iw, L, ew * rot)
               + cl.conjugate() * exp_integral_with(lam.conjugate() + iw, L, ew.conjugate() * rot))
    # int Y'^2, as integral_v2_with (UNDER) with e^{-2 zeta L}, cos 2wL, sin 2wL from the above
    C = r2 * q - r1 * p
    D = -(r2 * p + r1 * q)
    mean = 0.5 * (C * C + D * D)
    dc = 0.5 * (C * C - D * D)
    ds = C * D
    al = -2.0 * r1
    be = 2.0 * r2
    i0 = -math.expm1(al * L) / (-al) if al != 0.0 else L
    e2 = e * e
    cb = cw * cw - sw * sw
    sb = 2.0 * sw * cw
    den = al * al + be * be
    ic = (e2 * (al * cb + be * sb) - al) / den
    is_ = (e2 * (al * sb - be * cb) + be) / den
    return J, mean * i0 + dc * ic + ds * is_


# -- the work integrals of a forced phase from its start representation ---------------------------
# Over a piece [ta, tb] of a phase, X'^2 and X' f are sums of exponentials c e^{z t} (and constants), so
# int_ta^tb = Re(c (e^{z tb} - e^{z ta}) / z): the e^{z t} are products of e^{lam t} and e^{i Omega t},
# which the motion's own evaluation at tb gives (:func:`phase_exps`).  No phase is rebuilt per piece.
# The difference of two values of e^{z t} is exact up to their own rounding, which telescopes along a
# phase (the end of one piece is the start of the next): the sum over a phase is accurate to a few ulps
# of max |c / z| whatever the pieces.  Where |z| is small that scale is large; there (|z| < SMALL_RATE)
# each piece is integrated on its own, e^{z ta} times the series of exp_integral.
SMALL_RATE = 1.0 / 64.0


@njit(cache=True)
def phase_exps(co, dyn, omega, t):
    """(e^{lam t}, e^{i Omega t}) of a forced phase (:func:`forced_phase`) at t (see :func:`work_rep`).

    lam: OSC underdamped -zeta + i w; EXP -2 zeta (real); LIN 0.
    """
    reg, r1, r2, _, _ = co
    eo = complex(math.cos(omega * t), math.sin(omega * t))
    if dyn == OSC:
        e = math.exp(-r1 * t)
        return complex(e * math.cos(r2 * t), e * math.sin(r2 * t)), eo
    if dyn == EXP and r1 != 0.0:
        return complex(math.exp(-r1 * t), 0.0), eo
    return 1.0 + 0j, eo


@njit(cache=True)
def _slot(z, a, b):
    """One exponential e^{z t} of :func:`work_rep`: (z, A, B, per_piece) with A, B already divided by z unless per_piece."""
    if z.real * z.real + z.imag * z.imag < SMALL_RATE * SMALL_RATE:
        return z, a, b, True
    iz = reciprocal(z)
    return z, a * iz, b * iz, False


@njit(cache=True)
def work_rep(co, dyn, zeta, pz, fz, omega):
    """The work integrals of a phase as sums of exponentials: (slots, a0, b0) for :func:`work_between`.

    X'^2 = Re(sum A_k e^{z_k t}) + a0, X' f = Re(sum B_k e^{z_k t}) + b0, the five
    z_k of :func:`_exps`.  For OSC underdamped only (``co`` from
    :func:`forced_phase`), and the held motions LIN and EXP.
    """
    _, r1, r2, p, q = co
    zero = _slot(1.0 + 0j, 0j, 0j)
    iw = complex(0.0, omega)
    if dyn != OSC:  # X' = q e^{lam t}, lam = -r1 (EXP) or 0 (LIN): E = (e^{2 lam t}, e^{(lam + i Omega) t})
        lam = -r1 if dyn == EXP else 0.0
        if lam == 0.0:
            return (zero, _slot(iw, 0j, q * fz), zero, zero, zero), q * q, 0.0
        return (_slot(complex(2.0 * lam, 0.0), complex(q * q, 0.0), 0j), _slot(lam + iw, 0j, q * fz), zero, zero, zero), 0.0, 0.0
    lam = complex(-r1, r2)
    cl = complex(p, -q) * lam  # Y' = Re(cl e^{lam t})
    vz = iw * pz  # X_p' = Re(vz e^{i Omega t})
    lc = lam.conjugate()
    # Re(u e^{at}) Re(w e^{bt}) = Re(u w e^{(a+b)t} + u conj(w) e^{(a + conj b)t}) / 2
    s1 = _slot(lam + iw, cl * vz, 0.5 * cl * fz)
    s2 = _slot(lc + iw, cl.conjugate() * vz, 0.5 * cl.conjugate() * fz)
    s3 = _slot(2.0 * lam, 0.5 * cl * cl, 0j)
    s4 = _slot(lam + lc, complex(0.5 * (cl.real * cl.real + cl.imag * cl.imag), 0.0), 0j)
    s5 = _slot(2.0 * iw, 0.5 * vz * vz, 0.5 * vz * fz)
    return (s1, s2, s3, s4, s5), 0.5 * (vz.real * vz.real + vz.imag * vz.imag), 0.5 * (vz * fz.conjugate()).real


@njit(cache=True)
def _exps(dyn, el, eo):
    """The five e^{z_k t} of :func:`work_rep` from e^{lam t} and e^{i Omega t}."""
    if dyn != OSC:
        return el * el, el * eo, 0j, 0j, 0j
    lc = el.conjugate()
    return el * eo, lc * eo, el * el, el * lc, eo * eo


@njit(cache=True)
def _piece_slot(slot, ea, eb, L):
    """(Re A I, Re B I) of one slot, I the integral of e^{z t} over the piece (e^{z ta} = ea, e^{z tb} = eb)."""
    z, a, b, per_piece = slot
    d = ea * exp_integral(z, L) if per_piece else eb - ea
    return (a * d).real, (b * d).real


@njit(cache=True)
def work_between(rep, dyn, ela, eoa, elb, eob, L):
    """(int X'^2, int X' f) over [ta, tb], L = tb - ta, from e^{lam t}, e^{i Omega t} at both ends (:func:`phase_exps`)."""
    slots, a0, b0 = rep
    a1, a2, a3, a4, a5 = _exps(dyn, ela, eoa)
    b1, b2, b3, b4, b5 = _exps(dyn, elb, eob)
    v1, f1 = _piece_slot(slots[0], a1, b1, L)
    v2, f2 = _piece_slot(slots[1], a2, b2, L)
    v3, f3 = _piece_slot(slots[2], a3, b3, L)
    v4, f4 = _piece_slot(slots[3], a4, b4, L)
    v5, f5 = _piece_slot(slots[4], a5, b5, L)
    return (v1 + v2) + (v3 + v4) + v5 + a0 * L, (f1 + f2) + (f3 + f4) + f5 + b0 * L


@njit(cache=True)
def states(dyn, centre, x0, v0, s, theta, zeta, fex, omega, out_x, out_v):
    """X and X' a time ``s[i]`` into the phase of type ``dyn[i]`` started at (``x0[i]``, ``v0[i]``).

    The array form of :func:`state` and :func:`forced_eval` that trajectories
    are evaluated with between their samples: OSC phases about ``centre[i]``,
    with ``fex`` > 0 the particular solution of F_ex cos(Omega s + ``theta[i]``)
    added (LIN and EXP phases do not feel the force: the interface holds it).
    """
    for i in range(len(s)):
        if fex != 0.0:
            co, pz, fz = forced_phase(dyn[i], zeta, centre[i], x0[i], v0[i], fex, omega, theta[i])
            x, v, _, _, _, _, _, _ = forced_state(co, dyn[i], zeta, centre[i], pz, fz, omega, s[i])
        else:
            x, v, _ = state(dyn[i], zeta, centre[i], x0[i], v0[i], s[i])
        out_x[i] = x
        out_v[i] = v
