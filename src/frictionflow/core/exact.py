"""Exact event-driven integration of piecewise-constant friction laws.

Between switches the motion is a closed form (:mod:`.closed_form`); only the
switching instants are searched, by bracketed safeguarded Newton iteration on
the closed form, to about machine precision.  The friction modes:

============  ==========================================  ============
mode          friction force F_c                          motion
============  ==========================================  ============
SLIP_POS      +F_d   (V_r above the band / > 0)           OSC about F_d
SLIP_NEG      -F_d                                        OSC about -F_d
STICK         X + 2 zeta V_b (Coulomb: X' = V_b held)     LIN
HOLD          F_e (Karnopp band, |F_e| < F_s)             LIN or EXP
SAT_POS/NEG   +-F_s (Karnopp band, |F_e| >= F_s)          OSC about +-F_s
EDGE_LO/HI    X + 2 zeta X' (Filippov sliding on a band   LIN
              edge: Karnopp with F_e = X pushes the mass
              out of the band while slip pushes it back)
============  ==========================================  ============

Which mode follows a switch is decided by consistency: a mode is taken only if
the motion stays inside its region for a positive time, judged by the value
and the first two time derivatives of each of its boundary functions.  A
trajectory that touches a boundary within rounding without crossing it
(grazing) does not switch.

The kernel emits samples -- phase starts, zeros of X' (where X' is set to
exactly 0), extremes of X' and of X + 2 zeta X', the start of the tail, an
optional dense grid, and the end -- each with the exact cumulative work
integrals, so that the section records and the steady-state classifier of
:mod:`.sections` apply unchanged and see exact values.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import closed_form as cf
from .samples import emit
from .friction import COULOMB, FD, FS, KARNOPP, LAW, RESULTANT, VD

SLIP_POS, SLIP_NEG, HOLD, SAT_POS, SAT_NEG, EDGE_LO, EDGE_HI, STICK = range(1, 9)
FC_CONST, FC_RES, FC_SPRING = 0, 1, 2
KARNOPP_ORDER = np.array([SLIP_POS, SLIP_NEG, SAT_POS, SAT_NEG, HOLD, EDGE_LO, EDGE_HI])
COULOMB_ORDER = np.array([STICK, SLIP_POS, SLIP_NEG])

# status codes
DONE, FULL, STUCK = 0, 1, 2
EPS = 2.220446049250313e-16
MAX_EVENTS_PER_MODE = 5


@njit(cache=True)
def friction_mode(mode):
    """Recorded friction mode: +1 slip+, -1 slip-, 0 stick (band, edge)."""
    if mode == SLIP_POS:
        return 1
    if mode == SLIP_NEG:
        return -1
    return 0


@njit(cache=True)
def dynamics(mode, zeta, fd, fs, res):
    """(motion type, constant force, kind of F_c) of a mode."""
    if mode == SLIP_POS:
        return cf.OSC, fd, FC_CONST
    if mode == SLIP_NEG:
        return cf.OSC, -fd, FC_CONST
    if mode == SAT_POS:
        return cf.OSC, fs, FC_CONST
    if mode == SAT_NEG:
        return cf.OSC, -fs, FC_CONST
    if mode == HOLD and not res:
        return (cf.EXP if zeta > 0.0 else cf.LIN), 0.0, FC_SPRING
    return cf.LIN, 0.0, FC_RES


@njit(cache=True)
def friction_force(fck, force, x, v, zeta):
    if fck == FC_CONST:
        return force
    if fck == FC_SPRING:
        return x
    return x + 2.0 * zeta * v


@njit(cache=True)
def boundaries(mode, law, zeta, vb, fd, fs, vd, res, ev):
    """Fill ``ev[k] = (a, b, c, s)``: the mode holds while s (a X + b X' - c) > 0."""
    be = 2.0 * zeta if res else 0.0  # F_e = X + be X'
    n = 0
    if law == COULOMB:
        if mode == SLIP_POS:
            ev[0] = (0.0, 1.0, vb, -1.0)
            return 1
        if mode == SLIP_NEG:
            ev[0] = (0.0, 1.0, vb, 1.0)
            return 1
        # STICK at X' = V_b: F_e with X' = V_b
        ev[0] = (1.0, 0.0, fs - be * vb, -1.0)
        ev[1] = (1.0, 0.0, -fs - be * vb, 1.0)
        return 2
    lo = vb - vd  # lower band edge (V_r = +V_d)
    hi = vb + vd
    if mode == SLIP_POS:
        ev[0] = (0.0, 1.0, lo, -1.0)
        return 1
    if mode == SLIP_NEG:
        ev[0] = (0.0, 1.0, hi, 1.0)
        return 1
    if mode == EDGE_LO:
        ev[0] = (-1.0, -2.0 * zeta, -fd, 1.0)  # slip+ pushes back: F_d - X - 2 zeta X' > 0
        ev[1] = (0.0, 2.0 * zeta, 0.0, 1.0)  # the band pushes out: -2 zeta X' < 0
        ev[2] = (1.0, be, fs, -1.0)  # F_e < F_s
        return 3
    if mode == EDGE_HI:
        ev[0] = (1.0, 2.0 * zeta, -fd, 1.0)  # slip- pushes back: -F_d - X - 2 zeta X' < 0
        ev[1] = (0.0, 2.0 * zeta, 0.0, -1.0)  # the band pushes out: -2 zeta X' > 0
        ev[2] = (1.0, be, -fs, 1.0)  # F_e > -F_s
        return 3
    ev[0] = (0.0, 1.0, lo, 1.0)
    ev[1] = (0.0, 1.0, hi, -1.0)
    n = 2
    if mode == HOLD:
        ev[2] = (1.0, be, fs, -1.0)
        ev[3] = (1.0, be, -fs, 1.0)
        return 4
    if mode == SAT_POS:
        ev[2] = (1.0, be, fs, 1.0)
        return 3
    if mode == SAT_NEG:
        ev[2] = (1.0, be, -fs, -1.0)
        return 3
    return n


@njit(cache=True)
def _accel(dyn, zeta, force, x, v):
    if dyn == cf.OSC:
        a = force - x - 2.0 * zeta * v
        return a, -v - 2.0 * zeta * a
    if dyn == cf.EXP:
        a = -2.0 * zeta * v
        return a, -2.0 * zeta * a
    return 0.0, 0.0


@njit(cache=True)
def consistent(mode, law, zeta, vb, fd, fs, vd, res, x, v, ev):
    """Does the motion stay in ``mode``'s region for a positive time from (x, v)?"""
    # A switch is located to a few ulps of time; X' there is then off the boundary
    # by |X''| times that: far below this tolerance, far above rounding.
    vtol = 1e-10 * (abs(vb) + abs(v) + vd + abs(x) + fs)
    if law == KARNOPP and (mode == EDGE_LO or mode == EDGE_HI):
        edge = vb - vd if mode == EDGE_LO else vb + vd
        if abs(v - edge) > vtol:
            return False
        if res or zeta == 0.0:
            return False  # the band holds the mass itself: no sliding on its edge
    if law == COULOMB and mode == STICK and abs(v - vb) > vtol:
        return False
    dyn, force, _ = dynamics(mode, zeta, fd, fs, res)
    a, j = _accel(dyn, zeta, force, x, v)
    if law == COULOMB and mode == STICK:
        v = vb
        a = 0.0
        j = 0.0
    n = boundaries(mode, law, zeta, vb, fd, fs, vd, res, ev)
    for k in range(n):
        ca, cb, cc, s = ev[k, 0], ev[k, 1], ev[k, 2], ev[k, 3]
        g0 = s * (ca * x + cb * v - cc)
        tol0 = 256.0 * EPS * (abs(ca * x) + abs(cb * v) + abs(cc)) + 1e-300
        if g0 > tol0:
            continue
        if g0 < -tol0:
            return False
        g1 = s * (ca * v + cb * a)
        # X'' is a difference of terms of size |F| + |X| + 2 zeta |X'|: its rounding scale
        tol1 = 256.0 * EPS * (abs(ca * v) + abs(cb) * (abs(force) + abs(x) + 2.0 * zeta * abs(v))) + 1e-300
        if g1 > tol1:
            continue
        if g1 < -tol1:
            return False
        g2 = s * (ca * a + cb * j)
        if g2 < 0.0:
            return False
    return True


@njit(cache=True)
def select_mode(law, zeta, vb, fd, fs, vd, res, x, v, ev):
    """The mode the motion continues in from (x, v); -1 if none is consistent."""
    order = COULOMB_ORDER if law == COULOMB else KARNOPP_ORDER
    for m in order:
        if consistent(m, law, zeta, vb, fd, fs, vd, res, x, v, ev):
            return m
    return -1


@njit(cache=True)
def region_mode(law, zeta, vb, fd, fs, vd, res, x, v):
    """The mode by region alone (a fallback when no mode is consistent)."""
    be = 2.0 * zeta if res else 0.0
    if law == COULOMB:
        if v < vb:
            return SLIP_POS
        if v > vb:
            return SLIP_NEG
        return STICK
    if vb - v > vd:
        return SLIP_POS
    if vb - v < -vd:
        return SLIP_NEG
    fe = x + be * v
    if fe >= fs:
        return SAT_POS
    if fe <= -fs:
        return SAT_NEG
    return HOLD


@njit(cache=True, inline="always")
def _g(co, dyn, zeta, force, x0, v0, a, b, c, t):
    x, v, acc = cf.state_with(co, dyn, zeta, force, x0, v0, t)
    return a * x + b * v - c, a * v + b * acc


@njit(cache=True)
def _refine(co, dyn, zeta, force, x0, v0, a, b, c, s, lo, hi):
    """First time in (lo, hi] where s g <= 0, given s g(hi) <= 0 and g monotone on [lo, hi]."""
    t = 0.5 * (lo + hi)
    for _ in range(200):
        g, dg = _g(co, dyn, zeta, force, x0, v0, a, b, c, t)
        if s * g > 0.0:
            lo = t
        else:
            hi = t
        if hi - lo <= 2.0 * EPS * hi:
            break
        # Newton from the current point, kept inside the bracket
        tn = t - g / dg if dg != 0.0 else 0.5 * (lo + hi)
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        elif abs(tn - t) <= 2.0 * EPS * abs(tn):
            # converged to rounding: return the side of the root that is outside
            if s * g <= 0.0:
                return t
            tn = min(hi, t + 4.0 * EPS * abs(t))
            gn, _ = _g(co, dyn, zeta, force, x0, v0, a, b, c, tn)
            return tn if s * gn <= 0.0 else hi
        t = tn
    return hi


@njit(cache=True)
def _search(co, dyn, zeta, force, x0, v0, a, b, c, s, horizon, crit):
    """First crossing of one boundary in (0, horizon]: (time or inf, never crossed at all).

    g is monotone between its critical points; a crossing is bracketed on the
    first such interval whose end lies outside.  A critical point outside by
    less than 1e-12 of g's scale is a touch (grazing), not a crossing.
    ``never`` certifies that no crossing can come after the horizon either.
    """
    scale = abs(a * x0) + abs(b * v0) + abs(c) + 1e-300
    graze = 1e-12 * scale  # a critical point this close to the boundary only touches it
    tiny = 256.0 * EPS * scale  # a g that stays on the boundary (within rounding) does not cross it
    g_inf = s * (a * force - c)
    period = np.inf
    if dyn == cf.OSC and zeta == 0.0:
        period = 2.0 * math.pi
    if dyn == cf.LIN:
        # g = g0 + g1 t exactly: no bracketing needed (and none of its rounding)
        g0, g1 = _g(co, dyn, zeta, force, x0, v0, a, b, c, 0.0)
        if s * g1 >= 0.0:
            return np.inf, True
        tc = -g0 / g1
        if tc > horizon:
            return np.inf, False
        # the first representable time on the outside
        while s * _g(co, dyn, zeta, force, x0, v0, a, b, c, tc)[0] > 0.0:
            tc = np.nextafter(tc, np.inf)
        return max(tc, 0.0), False
    env, rate = cf.envelope(co, dyn, zeta, a, b)
    t_a = 0.0
    while True:
        m = cf.critical_points(co, dyn, a, b, t_a, horizon, crit)
        for i in range(m + 1):
            t_b = crit[i] if i < m else horizon
            gb, dgb = _g(co, dyn, zeta, force, x0, v0, a, b, c, t_b)
            if s * gb < -(graze if i < m else tiny):
                return _refine(co, dyn, zeta, force, x0, v0, a, b, c, s, t_a, t_b), False
            if g_inf > 0.0 and env * math.exp(-rate * t_b) < g_inf:
                return np.inf, True  # the decaying oscillation stays inside for ever
            if t_b >= period:
                return np.inf, True  # undamped: g repeats with period 2 pi
            t_a = t_b
        if m < len(crit) or t_a >= horizon:
            break
    # Nothing up to the horizon; after its last critical point g is monotone.
    gh, dgh = _g(co, dyn, zeta, force, x0, v0, a, b, c, horizon)
    if dyn == cf.LIN or (dyn == cf.EXP and zeta == 0.0):
        return np.inf, s * dgh >= 0.0
    if dyn == cf.EXP:
        return np.inf, g_inf_exp(zeta, x0, v0, a, b, c, s) > 0.0
    if dyn == cf.OSC and zeta >= 1.0:
        return np.inf, g_inf > 0.0 and cf.critical_points(co, dyn, a, b, horizon, np.inf, crit) == 0
    return np.inf, False


@njit(cache=True)
def g_inf_exp(zeta, x0, v0, a, b, c, s):
    """s g(inf) for the EXP motion (X -> x0 + v0 / (2 zeta), X' -> 0)."""
    return s * (a * (x0 + v0 / (2.0 * zeta)) - c)


@njit(cache=True)
def next_event(dyn, zeta, force, x0, v0, ev, n_ev, t_max, crit):
    """Earliest boundary crossing in (0, t_max]: (time, boundary index, never).

    ``never`` is True when no boundary can ever be crossed from here: the
    phase lasts for ever (the run has reached its final phase).
    """
    best = np.inf
    which = -1
    never = True
    co = cf.coefficients(dyn, zeta, force, x0, v0)
    for k in range(n_ev):
        tc, nv = _search(co, dyn, zeta, force, x0, v0, ev[k, 0], ev[k, 1], ev[k, 2], ev[k, 3], min(t_max, best), crit)
        if tc < best:
            best = tc
            which = k
        never = never and nv
    return best, which, never and which < 0


@njit(cache=True)
def _fc_zero(dyn, fck, zeta, x0, v0, t_max):
    """When a state-dependent F_c crosses 0 in (0, t_max) (P_f changes sign there), else -1."""
    if fck == FC_RES and v0 != 0.0:  # LIN: X + 2 zeta V_0 = x0 + v0 t + 2 zeta v0
        t = -(x0 + 2.0 * zeta * v0) / v0
    elif fck == FC_SPRING and v0 != 0.0:
        if dyn == cf.EXP:
            c = 2.0 * zeta
            arg = 1.0 + c * x0 / v0
            if not (0.0 < arg < 1.0):
                return -1.0
            t = -math.log(arg) / c
        else:
            t = -x0 / v0
    else:
        return -1.0
    return t if 0.0 < t < t_max else -1.0


@njit(cache=True)
def _piece(dyn, fck, zeta, vb, force, slipping, xa, va, xb, vb_, L, w):
    """Add the work integrals over one piece (P_f of one sign) to ``w``."""
    w[0] += 2.0 * zeta * cf.integral_v2(dyn, zeta, force, xa, va, L)
    if fck == FC_CONST:
        pf = force * (xb - xa)
    elif fck == FC_SPRING:
        pf = 0.5 * (xb * xb - xa * xa)
    else:
        pf = va * ((xa + 2.0 * zeta * va) * L + 0.5 * va * L * L)
    if pf > 0.0:
        w[1] += pf
    else:
        w[2] -= pf
    if slipping:
        w[3] += force * (vb * L - (xb - xa))


@njit(cache=True)
def run(x0, v0, t_end, zeta, vb, p, dense_dt, t_tail, stop_periodic, stop_terminal, rtol, min_periods,
        out_t, out_x, out_v, out_fc, out_mode, out_w, ev_t, ev_mode, t_mode):
    """Integrate from (x0, v0) at t = 0 to ``t_end`` switch by switch.

    Returns (samples, events, status, t_terminal, t_stop): ``t_terminal`` is
    when the final phase (from which no boundary is ever crossed again)
    began, or -1 (its friction mode goes to ``t_mode[0]``); ``t_stop`` where the run stopped early (``stop_periodic``:
    the section values repeated to ``rtol`` for ``min_periods`` periods;
    ``stop_terminal``: the final phase was reached), else ``t_end``.
    Status FULL means an output array was too short.
    """
    law = int(p[LAW])
    fd, fs, vd = p[FD], p[FS], p[VD]
    res = p[RESULTANT] != 0.0
    ev = np.empty((MAX_EVENTS_PER_MODE, 4))
    crit = np.empty(64)
    pts = np.empty(512 + (int(16.0 * math.pi / dense_dt) + 2 if dense_dt > 0.0 else 0))
    tags = np.zeros(len(pts), dtype=np.int8)  # 1: a zero of X'
    w = np.zeros(4)  # the work integrals since the last sample (emit restarts them)
    ring_x = np.full(min_periods + 2, np.nan)
    ring_t = np.full(min_periods + 2, np.nan)
    n_cross = 0
    xmax_seen = abs(x0)
    t = 0.0
    x, v = x0, v0
    mode = select_mode(law, zeta, vb, fd, fs, vd, res, x, v, ev)
    if mode < 0:
        mode = region_mode(law, zeta, vb, fd, fs, vd, res, x, v)
    if mode == STICK:
        v = vb
    k = 0
    ne = 0
    t_terminal = -1.0
    zero_len = 0
    dyn, force, fck = dynamics(mode, zeta, fd, fs, res)
    outs = (out_t, out_x, out_v, out_fc, out_mode, out_w)
    if not emit(outs, k, t, x, v, friction_force(fck, force, x, v, zeta), friction_mode(mode), w):
        return k, ne, FULL, t_terminal, t
    k += 1
    while t < t_end:
        dyn, force, fck = dynamics(mode, zeta, fd, fs, res)
        slipping = friction_mode(mode) != 0
        n_ev = boundaries(mode, law, zeta, vb, fd, fs, vd, res, ev)
        tau, which, never = next_event(dyn, zeta, force, x, v, ev, n_ev, t_end - t, crit)
        T = tau if which >= 0 else t_end - t
        if never and t_terminal < 0.0:
            t_terminal = t
            t_mode[0] = friction_mode(mode)
            if stop_terminal:
                return k, ne, DONE, t_terminal, t
        # Walk the phase in windows of 16 pi, emitting the samples inside.
        xp, vp = x, v  # phase start
        co = cf.coefficients(dyn, zeta, force, xp, vp)
        ta, xa, va = 0.0, x, v
        while ta < T:
            tw = min(T, ta + 16.0 * math.pi)
            n = 0
            m = cf.critical_points(co, dyn, 1.0, 0.0, ta, tw, crit)  # X' = 0
            for i in range(m):
                pts[n] = crit[i]
                tags[n] = 1
                n += 1
            nz = n
            m = cf.critical_points(co, dyn, 0.0, 1.0, ta, tw, crit)  # extremes of X'
            for i in range(m):
                pts[n] = crit[i]
                n += 1
            if zeta > 0.0:
                m = cf.critical_points(co, dyn, 1.0, 2.0 * zeta, ta, tw, crit)  # of X + 2 zeta X'
                for i in range(m):
                    pts[n] = crit[i]
                    n += 1
            tz = _fc_zero(dyn, fck, zeta, xp, vp, T)
            if ta < tz < tw:
                pts[n] = tz
                n += 1
            if ta < t_tail - t < tw:
                pts[n] = t_tail - t
                n += 1
            if dense_dt > 0.0:
                j = math.floor((t + ta) / dense_dt) + 1
                while j * dense_dt - t < tw and n < len(pts) - 1:
                    if j * dense_dt - t > ta:
                        pts[n] = j * dense_dt - t
                        n += 1
                    j += 1
            pts[n] = tw
            n += 1
            tags[nz:n] = 0
            _sort_tagged(pts, tags, n)
            for i in range(n):
                tb = pts[i]
                if tb <= ta:
                    continue
                if tb == tw and tw == T:
                    break  # the phase end is emitted after the switch
                xb, vb_, _ = cf.state_with(co, dyn, zeta, force, xp, vp, tb)
                vzero = tags[i] == 1
                if vzero:
                    vb_ = 0.0  # exactly: the section crossing is then a sample
                _piece(dyn, fck, zeta, vb, force, slipping, xa, va, xb, vb_, tb - ta, w)
                if not emit(outs, k, t + tb, xb, vb_, friction_force(fck, force, xb, vb_, zeta), friction_mode(mode), w):
                    return k, ne, FULL, t_terminal, t + ta
                k += 1
                ta, xa, va = tb, xb, vb_
                xmax_seen = max(xmax_seen, abs(xb))
                if vzero and stop_periodic and _falling(dyn, zeta, force, xp, vp, tb):
                    ring_x[n_cross % len(ring_x)] = xb
                    ring_t[n_cross % len(ring_t)] = t + tb
                    n_cross += 1
                    if _repeats(ring_x, ring_t, n_cross, min_periods, rtol * max(xmax_seen, abs(vb), fd, 1e-300), rtol):
                        return k, ne, DONE, t_terminal, t + tb
            if tw == T:
                # the last piece, up to the phase end
                xb, vb_, _ = cf.state_with(co, dyn, zeta, force, xp, vp, T)
                _piece(dyn, fck, zeta, vb, force, slipping, xa, va, xb, vb_, T - ta, w)
                ta, xa, va = T, xb, vb_
            else:
                ta = tw
        t += T
        x, v = xa, va
        if which < 0:
            break
        # The switch: which mode continues?
        new = select_mode(law, zeta, vb, fd, fs, vd, res, x, v, ev)
        if new < 0:
            new = region_mode(law, zeta, vb, fd, fs, vd, res, x, v)
        zero_len = zero_len + 1 if T <= 4.0 * EPS * (1.0 + t) else 0
        if zero_len > 8:
            return k, ne, STUCK, t_terminal, t
        mode = new
        if mode == STICK:
            v = vb
        if ne < len(ev_t):
            ev_t[ne] = t
            ev_mode[ne] = mode
        ne += 1
        dyn, force, fck = dynamics(mode, zeta, fd, fs, res)
        if not emit(outs, k, t, x, v, friction_force(fck, force, x, v, zeta), friction_mode(mode), w):
            return k, ne, FULL, t_terminal, t
        k += 1
    if out_t[k - 1] < t_end:
        dyn, force, fck = dynamics(mode, zeta, fd, fs, res)
        if not emit(outs, k, t_end, x, v, friction_force(fck, force, x, v, zeta), friction_mode(mode), w):
            return k, ne, FULL, t_terminal, t
        k += 1
    return k, ne, DONE, t_terminal, t_end


@njit(cache=True)
def _falling(dyn, zeta, force, xp, vp, tb):
    """X' goes from + to - at tb (a maximum of X)."""
    _, _, a = cf.state(dyn, zeta, force, xp, vp, tb)
    return a < 0.0


@njit(cache=True)
def _repeats(ring_x, ring_t, n, min_periods, tol_x, rtol):
    """The last min_periods + 1 maxima of X and their periods repeat."""
    if n < min_periods + 2:
        return False
    K = len(ring_x)
    last = (n - 1) % K
    p_last = ring_t[last] - ring_t[(n - 2) % K]
    for i in range(1, min_periods + 1):
        j = (n - 1 - i) % K
        if abs(ring_x[j] - ring_x[last]) > tol_x:
            return False
        pj = ring_t[j] - ring_t[(n - 2 - i) % K]
        if abs(pj - p_last) > rtol * p_last:
            return False
    return True


@njit(cache=True)
def _sort_tagged(pts, tags, n):
    """Insertion sort of pts[:n] carrying tags along (n is small; no allocation)."""
    for i in range(1, n):
        p = pts[i]
        g = tags[i]
        j = i - 1
        while j >= 0 and pts[j] > p:
            pts[j + 1] = pts[j]
            tags[j + 1] = tags[j]
            j -= 1
        pts[j + 1] = p
        tags[j + 1] = g
