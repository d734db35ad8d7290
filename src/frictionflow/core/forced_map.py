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
from collections import namedtuple

import numpy as np
from numba import njit

from .friction import FS, RESULTANT, external_force, external_force_rate, rest_mode
from .hermite import hermite_min
from .layout import FEX, N_WORK, OMEGA, W_DV, W_EX, W_FIN, W_FOUT
from .stick import held_along, next_turn
from .tangent import (
    saltation_reversal, saltation_slip, saltation_stick,
    C_GRAZE, C_HELD, C_REVERSAL, C_SLIP, C_STICK, EPS, MAX_ZERO_PHASES, N_COUNTS, NOT_FINITE, NY, OK, ZERO_PHASES,
    accel, rounding_noise, scratch, slip_force, slip_until, start_mode, stick_phase,
)

__all__ = ["flow_map", "map_out", "MapOut", "N_COUNTS", "N_STATS", "MAX_STICKS", "OK", "ZERO_PHASES", "NOT_FINITE",
           "C_STICK", "C_SLIP", "C_REVERSAL", "C_HELD", "C_GRAZE"]

#: stats slots: X_min, X_max, max |X + 2 zeta X'|, time sticking, smallest interior minimum of |V_r| in slip,
#: smallest margin F_s - |F_e - f| at an interior maximum of the held force in a stick phase, smallest overshoot
#: |F_e - f| - F_s at the held force's first turn after a break-away (were the mass held on)
S_XMIN, S_XMAX, S_QMAX, S_STICK_TIME, S_GAP, S_HOLD, S_EXIT = range(7)
N_STATS = 7
#: stick phases listed at most (more are counted but not listed)
MAX_STICKS = 256
#: pieces a stick interval is cut into when looking for sign changes of the held force
HOLD_PIECES = 4

# Module-level named tuples (numba types them as records; a kernel that takes them can still be cached).
#: what :func:`flow_map` fills (see there; :func:`map_out` allocates them)
MapOut = namedtuple("MapOut", "end mono work stats sticks counts")
#: the belt's scalars: zeta, V_b, the law's resultant rule and F_s (the arrays go apart: taking one out of a
#: record in the step loop would count its references there)
Belt = namedtuple("Belt", "zeta vb res fs")


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
    """The margin F_s - |F_e - f| where the held force turns away from F_s inside the stick piece (a, b).

    Its turns are :func:`.stick.next_turn`'s; (F_e - f)'' = -f'' = Omega^2 f,
    so a turn is a maximum (towards +F_s) where f < 0, a minimum where f > 0.
    """
    tm = next_turn(a, vb, p)
    while tm < b:
        side = -1.0 if external_force(p, tm) > 0.0 else 1.0
        margin = fs - side * held_along(x_s, t_s, tm, zeta, vb, res, p)
        stats[S_HOLD] = min(stats[S_HOLD], max(margin, 0.0))
        tm = next_turn(tm, vb, p)


@njit(cache=True)
def _track_exit(x_s, t_s, t, zeta, vb, res, fs, p, stats):
    """The overshoot beyond F_s of the held force at its first turn after a break-away at ``t``.

    The held force reaches F_s moving outwards and would turn at that turn;
    as the overshoot goes to 0 the break-away becomes tangent and the stick's
    end jumps to a later time (a grazing that ends a branch of orbits, with
    multipliers growing as 1 / sqrt(overshoot)).  Nothing where it never turns.
    """
    tm = next_turn(t, vb, p)
    if math.isfinite(tm):
        side = 1.0 if held_along(x_s, t_s, t, zeta, vb, res, p) > 0.0 else -1.0
        over = side * held_along(x_s, t_s, tm, zeta, vb, res, p) - fs
        stats[S_EXIT] = min(stats[S_EXIT], max(over, 0.0))


# -- the run ------------------------------------------------------------------------------------------------
def map_out() -> MapOut:
    """Fresh :class:`MapOut` buffers for :func:`flow_map`."""
    return MapOut(np.empty(2), np.empty((2, 2)), np.empty(N_WORK), np.empty(N_STATS), np.zeros((MAX_STICKS, 2)),
                  np.zeros(N_COUNTS, dtype=np.int64))


@njit(cache=True)
def _start(bl, p, x0, v0, y, out):
    """Clear ``out``'s sums and extremes; the state (x0, v0) and the identity into ``y``; returns the mode there."""
    for i in range(N_COUNTS):
        out.counts[i] = 0
    for i in range(N_WORK):
        out.work[i] = 0.0
    stats = out.stats
    stats[S_XMIN] = math.inf
    stats[S_XMAX] = -math.inf
    stats[S_QMAX] = 0.0
    stats[S_STICK_TIME] = 0.0
    stats[S_GAP] = math.inf
    stats[S_HOLD] = math.inf
    stats[S_EXIT] = math.inf
    y[0], y[1] = x0, v0
    y[2], y[3], y[4], y[5] = 1.0, 0.0, 0.0, 1.0
    mode = start_mode(x0, v0, 0.0, bl.zeta, bl.vb, p)
    if mode == 0:
        y[1] = bl.vb
        y[3] = 0.0  # sticking from the start: the stick onset's dv -> 0
        y[5] = 0.0
        out.sticks[0, 0] = 0.0
    _track_point(y[0], y[1], bl.zeta, stats)
    return mode


@njit(cache=True)
def _slip_onset(bl, p, y, t, out, n_sticks):
    """|F_e - f| reached F_s at t while sticking: (mode, n_sticks) after it.

    The mass slips away (the slip onset's saltation on ``y``'s tangents, the
    stick phase listed as ended) or, no slip direction being consistent, the
    interface holds on (mode 0).
    """
    zeta, vb = bl.zeta, bl.vb
    new = rest_mode(y[0], zeta, vb, bl.fs, bl.res, slip_force(p, 0.0), external_force(p, t), external_force_rate(p, t))
    if new == 0:
        out.counts[C_HELD] += 1
        return 0, n_sticks
    saltation_slip(y, new, t, zeta, vb, p)
    if n_sticks < MAX_STICKS:
        out.sticks[n_sticks, 1] = t
    out.counts[C_SLIP] += 1
    return new, n_sticks + 1


@njit(cache=True)
def _on_switch(bl, p, y, mode, t, out, n_sticks):
    """Slip in direction ``mode`` reached V_r = 0 at t: a stick onset, a reversal or a graze; returns (mode, fresh)."""
    zeta, vb = bl.zeta, bl.vb
    y[1] = vb  # exactly on the switch
    new = rest_mode(y[0], zeta, vb, bl.fs, bl.res, slip_force(p, 0.0), external_force(p, t), external_force_rate(p, t))
    if new == 0:
        saltation_stick(y)
        if n_sticks < MAX_STICKS:
            out.sticks[n_sticks, 0] = t
        out.counts[C_STICK] += 1
        return 0, False
    if new != mode:
        saltation_reversal(y, float(mode), new, t, zeta, vb, p)
        out.counts[C_REVERSAL] += 1
        return new, True
    out.counts[C_GRAZE] += 1  # touched V_r = 0 and slips on the same way: no switch
    return mode, True


@njit(cache=True)
def _finish(y, mode, span, out, n_sticks):
    """The end state and the monodromy into ``out``, a phase still sticking listed; returns (status, stick phases)."""
    if mode == 0:
        if n_sticks < MAX_STICKS:
            out.sticks[n_sticks, 1] = span
        n_sticks += 1
    out.end[0], out.end[1] = y[0], y[1]
    mono = out.mono
    mono[0, 0], mono[1, 0], mono[0, 1], mono[1, 1] = y[2], y[3], y[4], y[5]
    for i in range(2, NY):
        if not math.isfinite(y[i]):
            return NOT_FINITE, n_sticks
    return OK, n_sticks


@njit(cache=True)
def _walk(bl, p, y, mode, fresh, span, n_steps, out):
    """Advance ``y`` from tau = 0 in ``mode`` over the RK4 grid to ``span``; returns (status, mode, stick phases).

    The step loop itself, its buffers its own: the arrays it touches at
    every step are taken out of their records once, here (taking one out in
    the loop, or passing it to a helper there, would count its references
    at each step).  Switches, rarer, are helpers of their own.
    """
    zeta, vb, res, fs = bl
    work, stats = out.work, out.stats
    sc = scratch()  # the RK4 stages; a step's end state lands in sc.out
    end = sc.out
    g = np.empty((4, N_WORK))
    h = span / n_steps
    t = 0.0
    phase = stick_phase(y[0], 0.0, span, zeta, vb, p) if mode == 0 else (y[0], 0.0, span)
    n_sticks, zero_run = np.int64(0), 0  # (a literal 0: _slip_onset, _on_switch compiled once more)
    for j in range(1, n_steps + 1):
        target = span if j == n_steps else j * h
        while t < target:
            if mode == 0:
                x_s, t_s, te = phase
                leaves = te <= target and te < span
                t_next = te if leaves else target
                stick_work(x_s, t_s, t, t_next, zeta, vb, p, work)
                _track_hold(x_s, t_s, t, t_next, zeta, vb, res, fs, p, stats)
                stats[S_STICK_TIME] += t_next - t
                t = t_next
                y[0] = x_s + vb * (t - t_s)
                _track_point(y[0], y[1], zeta, stats)
                if leaves:
                    mode, n_sticks = _slip_onset(bl, p, y, t, out, n_sticks)
                    if mode != 0:
                        _track_exit(x_s, t_s, t, zeta, vb, res, fs, p, stats)
                    if mode == 0:  # held at F_s: on, as a new phase past the monotone piece it holds on
                        phase = stick_phase(y[0], t, span, zeta, vb, p)
                    fresh = fresh or mode != 0
                continue
            d = float(mode)
            x_a, v_a, t_a = y[0], y[1], t
            a_a = accel(d, x_a, v_a, t_a, zeta, vb, p)
            theta, switched = slip_until(y, t, target - t, d, zeta, vb, p, fresh, sc)
            if theta > 0.0 or not switched:
                dt = theta if switched else target - t_a
                work_step(x_a, v_a, t_a, dt, d, zeta, vb, p, work, g)
                for i in range(len(y)):
                    y[i] = end[i]
                t = t + theta if switched else target
                _track_step(x_a, v_a, a_a, y[0], y[1], accel(d, y[0], y[1], t, zeta, vb, p), dt, d, zeta, vb, stats,
                            not (fresh or switched))  # a step inside the phase: its interior minimum of |V_r| counts
            if not switched:
                zero_run = 0
                # a phase that has not yet left V_r = 0 by more than rounding is still starting
                fresh = fresh and not d * (vb - y[1]) > rounding_noise(y[1], vb)
                continue
            zero_run = zero_run + 1 if theta <= 4.0 * EPS * (1.0 + abs(t)) else 0
            if zero_run > MAX_ZERO_PHASES:
                return ZERO_PHASES, mode, n_sticks
            mode, fresh = _on_switch(bl, p, y, mode, t, out, n_sticks)
            if mode == 0:
                phase = stick_phase(y[0], t, span, zeta, vb, p)
    return OK, mode, n_sticks


@njit(cache=True)
def flow_map(x0, v0, zeta, vb, p, span, n_steps, out):
    """Integrate from (x0, v0) at tau = 0 to tau = ``span`` in ``n_steps`` RK4 grid steps; returns (status, stick phases).

    Fills the :class:`MapOut` buffers ``out`` (:func:`map_out`): ``end`` (X,
    X' at ``span``), ``mono`` (2 x 2: d(end)/d(x0, v0), the monodromy),
    ``work`` (:data:`~.layout.N_WORK` integrals over the span), ``stats``
    (:data:`N_STATS`: see ``S_*``), ``sticks`` (:data:`MAX_STICKS` x 2:
    start and end time of each stick phase; a phase still sticking at
    ``span`` ends there) and ``counts`` (:data:`~.tangent.N_COUNTS` switches).
    """
    bl = Belt(zeta, vb, p[RESULTANT] != 0.0, p[FS])
    y = np.zeros(NY)
    mode = _start(bl, p, x0, v0, y, out)
    status, mode, n_sticks = _walk(bl, p, y, mode, v0 == vb, span, n_steps, out)
    if status != OK:
        return status, n_sticks
    return _finish(y, mode, span, out, n_sticks)
