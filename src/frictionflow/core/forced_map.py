"""The flow map of the (forced) belt oscillator over a time span, with its Jacobian and the span's work integrals.

:func:`flow_map` integrates the state (X, X') from tau = 0 to tau = ``span``
together with two tangent vectors started at the identity, so that at the
end they are the columns of the map's Jacobian -- the monodromy matrix
M = dPhi/dP when the span is a whole number of forcing periods (the
stroboscopic map's derivative).  It is :func:`frictionflow.core.tangent.run`
without the per-block QR renormalisation: the phases, the switch location
and the three saltation matrices are that module's (imported, not copied;
its docstring derives them).  A stick phase leaves M of rank 1 (the stick
onset's saltation diag(1, 0)): one Floquet multiplier is then 0.

Along the way it integrates what an orbit's report needs, over the span:

* the work integrals of :mod:`frictionflow.core.layout` (W_dv, W_fin, W_fout,
  W_heat, W_ex): in slip by the same RK4 stages as the state (recomputed: an
  RK scheme applied to the augmented system gives the same X, X'), with the
  friction power split into max(P_f, 0) and max(-P_f, 0) at the stages as
  RK4's kernel does; in stick in closed form, where X' = V_b and the
  interface holds F_c = X + 2 zeta V_b - f(tau) (Newton's law with X'' = 0),
  split at the sign changes of F_c (found by bisection);
* extremes: X_min, X_max and max |X + 2 zeta X'| (TR_B's numerator), over
  the step ends and the interior extremes of each step's cubic Hermite
  interpolant;
* the time spent sticking, and each stick phase's (start, end);
* the smallest *interior* minimum of |V_r| inside a slip phase (a local
  minimum of the step's Hermite cubic, below both ends): how near the orbit
  is to a grazing that would start a new stick phase or a reversal;
* the smallest margin F_s - |F_e - f(tau)| at an interior maximum of the
  force a stick phase holds: how near the orbit is to a stick phase that
  breaks in two (the held force touching F_s).  There the map is
  discontinuous when F_s > F(0+): the mass that slips at the touch leaves
  with the finite acceleration F_s - F(0+).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .friction import FS, RESULTANT, external_force, external_force_rate, rest_mode
from .hermite import hermite_min
from .layout import FEX, N_WORK, OMEGA, W_DV, W_EX, W_FIN, W_FOUT
from .tangent import (
    saltation_reversal, saltation_slip, saltation_stick,
    C_GRAZE, C_HELD, C_REVERSAL, C_SLIP, C_STICK, EPS, MAX_ZERO_PHASES, N_COUNTS, NOT_FINITE, NY, OK, ZERO_PHASES,
    _stick_gap, _stick_gap_rate, _stick_max, accel, rounding_noise, scratch, slip_force, slip_until,
    start_mode, stick_exit,
)

__all__ = ["flow_map", "N_COUNTS", "N_STATS", "MAX_STICKS", "OK", "ZERO_PHASES", "NOT_FINITE",
           "C_STICK", "C_SLIP", "C_REVERSAL", "C_HELD", "C_GRAZE"]

#: stats slots: X_min, X_max, max |X + 2 zeta X'|, time sticking, smallest interior minimum of |V_r| in slip,
#: smallest margin F_s - |F_e - f| at an interior maximum of the held force in a stick phase
S_XMIN, S_XMAX, S_QMAX, S_STICK_TIME, S_GAP, S_HOLD = range(6)
N_STATS = 6
#: stick phases listed at most (more are counted but not listed)
MAX_STICKS = 256
#: pieces a stick interval is cut into when looking for sign changes of the held force
HOLD_PIECES = 4


@njit(cache=True)
def _slip_power(x, v, t, d, zeta, vb, p, out):
    """X'' while slipping in direction d; the work integrands (P_dv, P_f+, P_f-, P_heat, P_ex) into ``out``."""
    s = d * (vb - v)
    mag = slip_force(p, s)
    fext = external_force(p, t)
    fc = d * mag
    pf = v * fc
    out[0] = 2.0 * zeta * v * v
    out[1] = max(pf, 0.0)
    out[2] = max(-pf, 0.0)
    out[3] = mag * s
    out[4] = v * fext
    return fc + fext - x - 2.0 * zeta * v


@njit(cache=True)
def work_step(x, v, t, h, d, zeta, vb, p, w, g):
    """Add the work integrals of one RK4 slip step of length h from (x, v, t) to ``w`` (``g``: 4 x 5 scratch)."""
    a1 = _slip_power(x, v, t, d, zeta, vb, p, g[0])
    x2, v2 = x + 0.5 * h * v, v + 0.5 * h * a1
    a2 = _slip_power(x2, v2, t + 0.5 * h, d, zeta, vb, p, g[1])
    x3, v3 = x + 0.5 * h * v2, v + 0.5 * h * a2
    a3 = _slip_power(x3, v3, t + 0.5 * h, d, zeta, vb, p, g[2])
    x4, v4 = x + h * v3, v + h * a3
    _slip_power(x4, v4, t + h, d, zeta, vb, p, g[3])
    for i in range(N_WORK):
        w[i] += h / 6.0 * (g[0, i] + 2.0 * g[1, i] + 2.0 * g[2, i] + g[3, i])


@njit(cache=True)
def force_integral(p, t):
    """An antiderivative of f(t) = F_ex cos(Omega t + phi): (F_ex / Omega) sin(Omega t + phi) (0 unforced)."""
    if p[FEX] == 0.0:
        return 0.0
    return -external_force_rate(p, t) / (p[OMEGA] * p[OMEGA])


@njit(cache=True)
def _held(c0, t, vb, p):
    """The force the interface holds while sticking, X + 2 zeta V_b - f(t), with X + 2 zeta V_b = c0 + V_b t."""
    return c0 + vb * t - external_force(p, t)


@njit(cache=True)
def _add_held_work(c0, a, b, vb, p, w):
    """The friction work V_b int_a^b F_c dt of a piece on which F_c keeps its sign, into W_fin or W_fout."""
    lin = c0 * (b - a) + 0.5 * vb * (b * b - a * a)
    work = vb * (lin - (force_integral(p, b) - force_integral(p, a)))
    if work >= 0.0:
        w[W_FIN] += work
    else:
        w[W_FOUT] -= work


@njit(cache=True)
def stick_work(x_s, t_s, a, b, zeta, vb, p, w):
    """Add the work integrals of sticking over [a, b] (X' = V_b, X = x_s + V_b (t - t_s)) to ``w``.

    P_dv = 2 zeta V_b^2 and P_ex = V_b f(t) in closed form; the friction
    power V_b F_c split where F_c changes sign (a line minus a cosine: its
    roots are bracketed on :data:`HOLD_PIECES` pieces and bisected); no heat.
    """
    if b <= a:
        return
    w[W_DV] += 2.0 * zeta * vb * vb * (b - a)
    w[W_EX] += vb * (force_integral(p, b) - force_integral(p, a))
    c0 = x_s - vb * t_s + 2.0 * zeta * vb
    lo = a
    flo = _held(c0, a, vb, p)
    for k in range(1, HOLD_PIECES + 1):
        hi = a + (b - a) * k / HOLD_PIECES if k < HOLD_PIECES else b
        fhi = _held(c0, hi, vb, p)
        if flo * fhi < 0.0:
            r_lo, r_hi = lo, hi
            for _ in range(200):
                m = 0.5 * (r_lo + r_hi)
                if m <= r_lo or m >= r_hi:
                    break
                if _held(c0, m, vb, p) * flo > 0.0:
                    r_lo = m
                else:
                    r_hi = m
            _add_held_work(c0, lo, r_hi, vb, p, w)
            lo = r_hi
        if hi > lo:
            _add_held_work(c0, lo, hi, vb, p, w)
        lo, flo = hi, fhi


@njit(cache=True)
def _hermite_max(f0, f1, m0, m1):
    """The largest value of the cubic Hermite interpolant on [0, 1] (ends included)."""
    s, val = hermite_min(-f0, -f1, -m0, -m1)
    top = max(f0, f1)
    return max(top, -val) if s >= 0.0 else top


@njit(cache=True)
def _track_step(x0, v0, a0, x1, v1, a1, h, d, zeta, vb, stats, interior):
    """Update the extremes with a slip step from (x0, v0, X''=a0) to (x1, v1, a1) of length h.

    ``interior``: the step lies inside a slip phase (neither starts nor ends
    it), so a local minimum of |V_r| = d (V_b - X') inside it counts.
    """
    stats[S_XMAX] = max(stats[S_XMAX], _hermite_max(x0, x1, v0 * h, v1 * h))
    stats[S_XMIN] = min(stats[S_XMIN], -_hermite_max(-x0, -x1, -v0 * h, -v1 * h))
    q0 = x0 + 2.0 * zeta * v0
    q1 = x1 + 2.0 * zeta * v1
    m0 = (v0 + 2.0 * zeta * a0) * h
    m1 = (v1 + 2.0 * zeta * a1) * h
    stats[S_QMAX] = max(stats[S_QMAX], _hermite_max(q0, q1, m0, m1), _hermite_max(-q0, -q1, -m0, -m1))
    if interior:
        g0 = d * (vb - v0)
        g1 = d * (vb - v1)
        s, val = hermite_min(g0, g1, -d * a0 * h, -d * a1 * h)
        if s >= 0.0 and val <= min(g0, g1):
            stats[S_GAP] = min(stats[S_GAP], max(val, 0.0))


@njit(cache=True)
def _track_point(x, v, zeta, stats):
    stats[S_XMAX] = max(stats[S_XMAX], x)
    stats[S_XMIN] = min(stats[S_XMIN], x)
    stats[S_QMAX] = max(stats[S_QMAX], abs(x + 2.0 * zeta * v))


@njit(cache=True)
def _track_hold(x_s, t_s, a, b, zeta, vb, res, fs, p, stats):
    """The margin F_s - |F_e - f| at interior maxima of either side's held force on the stick piece [a, b]."""
    if b <= a:
        return
    for side in (1.0, -1.0):
        if _stick_gap_rate(a, side, vb, p) > 0.0 and _stick_gap_rate(b, side, vb, p) < 0.0:
            tm = _stick_max(a, b, side, vb, p)
            stats[S_HOLD] = min(stats[S_HOLD], max(-_stick_gap(x_s, t_s, tm, side, zeta, vb, res, fs, p), 0.0))


@njit(cache=True)
def flow_map(x0, v0, zeta, vb, p, span, n_steps, end, mono, work, stats, sticks, counts):
    """Integrate from (x0, v0) at tau = 0 to tau = ``span`` in ``n_steps`` RK4 grid steps; returns (status, stick phases).

    Fills ``end`` (X, X' at ``span``), ``mono`` (2 x 2: d(end)/d(x0, v0), the
    monodromy), ``work`` (:data:`~.layout.N_WORK` integrals over the span),
    ``stats`` (:data:`N_STATS`: see ``S_*``), ``sticks`` (:data:`MAX_STICKS`
    x 2: start and end time of each stick phase; a phase still sticking at
    ``span`` ends there) and ``counts`` (:data:`~.tangent.N_COUNTS` switches).
    """
    res = p[RESULTANT] != 0.0
    fs = p[FS]
    h = span / n_steps
    y = np.zeros(NY)
    sc = scratch()
    out = sc.out
    g = np.empty((4, N_WORK))
    for i in range(N_COUNTS):
        counts[i] = 0
    for i in range(N_WORK):
        work[i] = 0.0
    stats[S_XMIN] = math.inf
    stats[S_XMAX] = -math.inf
    stats[S_QMAX] = 0.0
    stats[S_STICK_TIME] = 0.0
    stats[S_GAP] = math.inf
    stats[S_HOLD] = math.inf
    n_sticks = 0
    y[0], y[1] = x0, v0
    y[2], y[3], y[4], y[5] = 1.0, 0.0, 0.0, 1.0
    t = 0.0
    mode = start_mode(x0, v0, t, zeta, vb, p)
    x_s, t_s = x0, 0.0  # where the current stick phase began
    if mode == 0:
        y[1] = vb
        y[3] = 0.0  # sticking from the start: the stick onset's dv -> 0
        y[5] = 0.0
        sticks[0, 0] = 0.0
    fresh = v0 == vb
    _track_point(y[0], y[1], zeta, stats)
    zero_run = 0
    for j in range(1, n_steps + 1):
        target = span if j == n_steps else j * h
        while t < target:
            if mode == 0:
                te, side = stick_exit(x_s, t_s, t, target, zeta, vb, res, fs, p)
                t_next = target if side == 0 else te
                stick_work(x_s, t_s, t, t_next, zeta, vb, p, work)
                _track_hold(x_s, t_s, t, t_next, zeta, vb, res, fs, p, stats)
                stats[S_STICK_TIME] += t_next - t
                t = t_next
                y[0] = x_s + vb * (t - t_s)
                _track_point(y[0], y[1], zeta, stats)
                if side == 0:
                    continue
                new = rest_mode(y[0], zeta, vb, fs, res, slip_force(p, 0.0), external_force(p, t),
                                external_force_rate(p, t))
                if new == 0:
                    counts[C_HELD] += 1  # no slip direction is consistent: the interface holds on
                    continue
                saltation_slip(y, new, t, zeta, vb, p)
                if n_sticks < MAX_STICKS:
                    sticks[n_sticks, 1] = t
                n_sticks += 1
                mode = new
                fresh = True
                counts[C_SLIP] += 1
                continue
            d = float(mode)
            was_fresh = fresh
            x_a, v_a, t_a = y[0], y[1], t
            a_a = accel(d, x_a, v_a, t_a, zeta, vb, p)
            theta, switched = slip_until(y, t, target - t, d, zeta, vb, p, fresh, sc)
            if not switched:
                work_step(x_a, v_a, t_a, target - t_a, d, zeta, vb, p, work, g)
                for i in range(len(y)):
                    y[i] = out[i]
                t = target
                zero_run = 0
                # a phase that has not yet left V_r = 0 by more than rounding is still starting
                fresh = fresh and not d * (vb - y[1]) > rounding_noise(y[1], vb)
                _track_step(x_a, v_a, a_a, y[0], y[1], accel(d, y[0], y[1], t, zeta, vb, p), t - t_a, d, zeta, vb,
                            stats, not was_fresh)
                continue
            fresh = False
            if theta > 0.0:
                work_step(x_a, v_a, t_a, theta, d, zeta, vb, p, work, g)
                for i in range(len(y)):
                    y[i] = out[i]
                t += theta
                _track_step(x_a, v_a, a_a, y[0], y[1], accel(d, y[0], y[1], t, zeta, vb, p), theta, d, zeta, vb,
                            stats, False)
            zero_run = zero_run + 1 if theta <= 4.0 * EPS * (1.0 + abs(t)) else 0
            if zero_run > MAX_ZERO_PHASES:
                return ZERO_PHASES, n_sticks
            y[1] = vb  # exactly on the switch
            new = rest_mode(y[0], zeta, vb, fs, res, slip_force(p, 0.0), external_force(p, t),
                            external_force_rate(p, t))
            if new == 0:
                saltation_stick(y)
                x_s, t_s = y[0], t
                if n_sticks < MAX_STICKS:
                    sticks[n_sticks, 0] = t
                mode = 0
                counts[C_STICK] += 1
            elif new != mode:
                saltation_reversal(y, d, new, t, zeta, vb, p)
                mode = new
                fresh = True
                counts[C_REVERSAL] += 1
            else:
                counts[C_GRAZE] += 1  # touched V_r = 0 and slips on the same way: no switch
                fresh = True
    if mode == 0:
        if n_sticks < MAX_STICKS:
            sticks[n_sticks, 1] = span
        n_sticks += 1
    end[0], end[1] = y[0], y[1]
    mono[0, 0], mono[1, 0], mono[0, 1], mono[1, 1] = y[2], y[3], y[4], y[5]
    for i in range(2, NY):
        if not math.isfinite(y[i]):
            return NOT_FINITE, n_sticks
    return OK, n_sticks
