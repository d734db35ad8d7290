"""Classical fixed-step RK4 (the paper's method), friction evaluated at every stage.

The state is augmented with four work integrals so that power-flow averages
are integrated by the same RK4 quadrature as the motion (each sample records
what accumulated since the previous one, then the sums restart):

* ``W_dv``   = int 2 zeta X'^2            (damper)
* ``W_pos``  = int max(P_f, 0)            (friction power in, P_f = X' F_c)
* ``W_neg``  = int max(-P_f, 0)           (friction power out, as a magnitude)
* ``W_heat`` = int F_c V_r over slip      (heat at the interface)
* ``W_ex``   = int X' f(tau)              (work of the external force)

The external force enters each stage at the stage's time; a step evaluates
it at its start, middle and end (``f1``, ``f2``, ``f4``), the last reused as
the next step's start.  Unforced runs pass zeros and compute no cosine.  A
belt whose speed varies is evaluated at the same three times: its speed
V_b(tau) and the load f - V_b' the stick band holds (:func:`drive_at`);
on a constant belt the load is f itself and the speed V_b, to the bit.

``s`` (length 7) holds ``X, X'`` and the five sums since the last sample; it is
updated in place, so a long run can be advanced chunk by chunk (progress bars).

The kernels take records rather than long lists: ``span`` = (i0, i1,
n_total, every), the steps to advance and the sampling; ``out``, the output
buffers :class:`~frictionflow.core.records.Samples`; inside, the law's band
record (:func:`~frictionflow.core.friction.band_law`) and a step's external
force ``fx`` = (f1, f2, f4).  Tuples of scalars cost nothing once inlined.
"""

from __future__ import annotations

import math
import sys

from numba import njit

from .friction import (COULOMB, CUBIC, KARNOPP, LAW, SMOOTH_LAWS, STRIBECK, FASTMATH, VB_AMP, band_force, band_force_select,
                       band_law, band_mode, belt_accel, belt_speed, external_force)

N_STATE = 7
#: the slot of V_d in a band record (:func:`band_law`)
_VD = 3
#: a step without external force
NO_FORCE = (0.0, 0.0, 0.0)


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def constant_drive(vb):
    """A step's drive without external force on a belt at constant speed ``vb``: (f, load, V_b) at its three times."""
    return NO_FORCE, NO_FORCE, (vb, vb, vb)


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def drive_at(p, vb, t):
    """(f, f - V_b', V_b) at ``t``: the external force, the load the stick band holds and the belt's speed (on a constant
    belt the load is f and the speed ``vb``, no sine computed)."""
    f = external_force(p, t)
    if p[VB_AMP] == 0.0:
        return f, f, vb
    return f, f - belt_accel(p, t), belt_speed(p, vb, t)
#: the smooth laws :func:`run` and the batched block (:mod:`.rk4_batch`) branch on, one branch each (typing a loop
#: over them with ``literal_unroll`` costs seconds of compiling): a law added to SMOOTH_LAWS needs its branches
BRANCHED_LAWS = (STRIBECK, CUBIC)
if SMOOTH_LAWS != BRANCHED_LAWS:  # pragma: no cover - caught when a law is added
    raise ImportError(f"core.rk4.run and core.rk4_batch._block branch on the laws {BRANCHED_LAWS}, not on SMOOTH_LAWS "
                      f"{SMOOTH_LAWS}: add the new law's branches")


#: relative rounding of t_end / dt allowed for when counting steps (a few ulps: t_end and dt are each rounded,
#: a forced run's dt a quotient of the forcing period)
STEP_ROUNDING = 8 * sys.float_info.epsilon


def step_count(t_end: float, dt: float) -> int:
    """Steps of ``dt`` that reach ``t_end`` (at least 1): a quotient t_end / dt that is a whole number but for its
    rounding is that number, not one more (a run ended a step past t_end when t_end is a whole number of forcing
    periods, t_end / dt ~ 1e7 to 1e8: its rounding, a few ulps, is more than 1e-9 there)."""
    x = t_end / dt
    return max(1, math.ceil(x - max(1e-9, STEP_ROUNDING * x)))


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def stage(x, v, drive, zeta, lw, lanes, forced):
    """Right-hand side at one stage with ``drive`` = (f, load, V_b) there: (X'', P_dv, P_f+, P_f-, P_heat).

    ``lw``: the law's band record.  ``lanes`` and ``forced`` (constants at
    each call site) pick the select form of the law for the batched kernels,
    and whether an external force acts: unforced loops then hold no trace of
    it (``f`` is a constant 0.0).  The band holds the load f - V_b'.
    """
    f, g, vb = drive
    if lanes:
        fc = band_force_select(lw, x, v, zeta, vb, g)
    else:
        fc = band_force(lw, x, v, zeta, vb, g)
    a = fc - x - 2.0 * zeta * v
    if forced:
        a += f
    pf = v * fc
    vr = vb - v
    heat = fc * vr if abs(vr) > lw[_VD] else 0.0
    return a, 2.0 * zeta * v * v, max(pf, 0.0), max(-pf, 0.0), heat


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def step(x, v, dt, zeta, lw, lanes, drive, forced):
    """One RK4 step of the augmented system; returns new X, X' and work increments (W_ex's last).

    ``drive`` = (fx, gx, vbs), each at the step's start, middle and end: the
    external force (read only when ``forced``, a constant at each call site),
    the load the band holds and the belt's speed (:func:`constant_drive`,
    :func:`drive_at`).
    """
    fx, gx, vbs = drive
    f1, f2, f4 = fx
    h2 = 0.5 * dt
    a1, d1, p1, n1, q1 = stage(x, v, (f1, gx[0], vbs[0]), zeta, lw, lanes, forced)
    x2 = x + h2 * v
    v2 = v + h2 * a1
    mid = (f2, gx[1], vbs[1])
    a2, d2, p2, n2, q2 = stage(x2, v2, mid, zeta, lw, lanes, forced)
    x3 = x + h2 * v2
    v3 = v + h2 * a2
    a3, d3, p3, n3, q3 = stage(x3, v3, mid, zeta, lw, lanes, forced)
    x4 = x + dt * v3
    v4 = v + dt * a3
    a4, d4, p4, n4, q4 = stage(x4, v4, (f4, gx[2], vbs[2]), zeta, lw, lanes, forced)
    h6 = dt / 6.0
    return (
        x + h6 * (v + 2.0 * v2 + 2.0 * v3 + v4),
        v + h6 * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
        h6 * (d1 + 2.0 * d2 + 2.0 * d3 + d4),
        h6 * (p1 + 2.0 * p2 + 2.0 * p3 + p4),
        h6 * (n1 + 2.0 * n2 + 2.0 * n3 + n4),
        h6 * (q1 + 2.0 * q2 + 2.0 * q3 + q4),
        h6 * (v * f1 + 2.0 * (v2 + v3) * f2 + v4 * f4) if forced else 0.0,
    )


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def _sample(x, v, g, zeta, vb, lw):
    """(F_c, friction mode) of the state (X, X') under the load ``g`` on a belt at ``vb``: what a sample records besides it."""
    return band_force(lw, x, v, zeta, vb, g), band_mode(v, vb, lw[_VD])


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _record(out, k, t, x, v, fm, w):
    """Sample ``k`` into the buffers ``out``: the state, ``fm`` (:func:`_sample`), the work ``w`` since the last one.

    Plain stores only: a call or a branch here (``_sample``'s) would keep
    numba's reference counts on ``out``'s arrays, atomic operations per sample.
    """
    out.t[k] = t
    out.y[0, k] = x
    out.y[1, k] = v
    out.fc[0, k] = fm[0]
    out.mode[0, k] = fm[1]
    out.work[k, 0] = w[0]
    out.work[k, 1] = w[1]
    out.work[k, 2] = w[2]
    out.work[k, 3] = w[3]
    out.work[k, 4] = w[4]


@njit(cache=True, fastmath=FASTMATH)
def run(s, span, t0, dt, zeta, vb, p, out, k):
    """Advance steps ``i0 .. i1-1`` (global indices) of ``span`` = (i0, i1, n_total, every), recording every ``every``-th.

    A sample is written into ``out`` (:class:`~frictionflow.core.records.Samples`)
    before step ``i`` when ``i % every == 0`` and after the last step
    (``i1 == n_total``).  Returns the next free sample index.  Each law's loop
    is compiled with its code as a constant, so that it holds only that
    law's slip force.  Unforced: a force record with F_ex > 0 goes to
    :func:`run_forced` (the façade chooses, so that unforced runs compile no
    forced loop; a moving belt goes there too).

    The codes are passed as ``code + 0``: a plain integer to numba, so that
    ``_run`` is typed once for all laws (not once per constant, nor once per
    branch: LLVM inlines it), and still a constant to LLVM, which folds the
    other laws' branches after inlining (:data:`BRANCHED_LAWS`).
    """
    law = int(p[LAW])
    if law == KARNOPP or law == COULOMB:
        return _run(KARNOPP + 0, False, s, span, t0, dt, zeta, vb, p, out, k)
    if law == STRIBECK:
        return _run(STRIBECK + 0, False, s, span, t0, dt, zeta, vb, p, out, k)
    if law == CUBIC:
        return _run(CUBIC + 0, False, s, span, t0, dt, zeta, vb, p, out, k)
    return k


@njit(cache=True, fastmath=FASTMATH)
def run_forced(s, span, t0, dt, zeta, vb, p, out, k):
    """:func:`run` under the external force or the moving belt of ``p``: one loop for every law (the cosines dominate it)."""
    return _run(int(p[LAW]), True, s, span, t0, dt, zeta, vb, p, out, k)


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def _run(law, forced, s, span, t0, dt, zeta, vb, p, out, k):
    i0, i1, n_total, every = span
    lw = band_law(law, p)
    x, v, w0, w1, w2, w3, w4 = s[0], s[1], s[2], s[3], s[4], s[5], s[6]
    d1_ = d2_ = d4_ = (0.0, 0.0, vb)  # the drive (f, load, V_b) at the step's start, middle and end
    if forced:
        d1_ = drive_at(p, vb, t0 + i0 * dt)
    # a countdown instead of i % every: an integer division per step costs more than the step
    due = (every - i0 % every) % every
    for i in range(i0, i1):
        if due == 0:
            due = every
            _record(out, k, t0 + i * dt, x, v, _sample(x, v, d1_[1], zeta, d1_[2], lw), (w0, w1, w2, w3, w4))
            k += 1
            w0 = w1 = w2 = w3 = w4 = 0.0
        due -= 1
        if forced:
            d2_ = drive_at(p, vb, t0 + (i + 0.5) * dt)
            d4_ = drive_at(p, vb, t0 + (i + 1) * dt)
        x, v, d0, d1, d2, d3, d4 = step(x, v, dt, zeta, lw, False, _tabled(d1_, d2_, d4_), forced)
        w0 += d0
        w1 += d1
        w2 += d2
        w3 += d3
        if forced:
            w4 += d4
            d1_ = d4_
    if i1 == n_total:
        _record(out, k, t0 + n_total * dt, x, v, _sample(x, v, d1_[1], zeta, d1_[2], lw), (w0, w1, w2, w3, w4))
        k += 1
        w0 = w1 = w2 = w3 = w4 = 0.0
    s[0], s[1], s[2], s[3], s[4], s[5], s[6] = x, v, w0, w1, w2, w3, w4
    return k


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def _tabled(a, b, c):
    """The drives (f, load, V_b) at a step's three times as :func:`step` takes them: (fx, gx, vbs)."""
    return (a[0], b[0], c[0]), (a[1], b[1], c[1]), (a[2], b[2], c[2])


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def _sign(u):
    return (u > 0.0) - (u < 0.0)


@njit(cache=True, fastmath=FASTMATH)
def run_thinned(s, span, t0, dt, t_tail, zeta, vb, p, out, k):
    """As :func:`run` keeping every ``every``-th step, and both steps around every event the analysis reads.

    The events: a sign change of X' (section crossings, extremes of X), of X''
    (extremes of X'), of X' + 2 zeta X'' (extremes of the wall force), a change
    of friction mode, and the start of the tail ``t_tail``.  Between two kept
    samples none of these happens, so the section records, window aggregates
    and stick times built from the kept samples are those of every step
    (:func:`frictionflow.core.sections.records_from_samples`), and the work
    integrals are exact sums.  ``s`` (length N_STATE + 2) also carries X'' of
    the current state and whether it is kept already.  Returns (next free
    sample, next step): it stops early when fewer than 3 samples fit.
    Unforced: the external force's variant is :func:`run_thinned_forced`.
    """
    return _thinned(False, s, span, t0, dt, t_tail, zeta, vb, p, out, k)


@njit(cache=True, fastmath=FASTMATH)
def run_thinned_forced(s, span, t0, dt, t_tail, zeta, vb, p, out, k):
    """:func:`run_thinned` under the external force or the moving belt of ``p``."""
    return _thinned(True, s, span, t0, dt, t_tail, zeta, vb, p, out, k)


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _thinned(forced, s, span, t0, dt, t_tail, zeta, vb, p, out, k):
    i0, i1, n_total, every = span
    lw = band_law(int(p[LAW]), p)
    vd = lw[_VD]
    x, v, w0, w1, w2, w3, w4 = s[0], s[1], s[2], s[3], s[4], s[5], s[6]
    a, kept = s[N_STATE], s[N_STATE + 1] != 0.0
    cap = len(out.t)
    i = i0
    d1_ = d2_ = d4_ = (0.0, 0.0, vb)  # the drive (f, load, V_b) at the step's start, middle and end
    if forced:
        d1_ = drive_at(p, vb, t0 + i0 * dt)
    while i < i1:
        if k + 3 > cap:
            break
        t = t0 + i * dt
        if i % every == 0 and not kept:
            _record(out, k, t, x, v, _sample(x, v, d1_[1], zeta, d1_[2], lw), (w0, w1, w2, w3, w4))
            k += 1
            w0 = w1 = w2 = w3 = w4 = 0.0
            kept = True
        if forced:
            d2_ = drive_at(p, vb, t0 + (i + 0.5) * dt)
            d4_ = drive_at(p, vb, t0 + (i + 1) * dt)
        xn, vn, d0, d1, d2, d3, d4 = step(x, v, dt, zeta, lw, False, _tabled(d1_, d2_, d4_), forced)
        an = band_force(lw, xn, vn, zeta, d4_[2], d4_[1]) - xn - 2.0 * zeta * vn
        if forced:
            an += d4_[0]
        event = (_sign(v) != _sign(vn) or _sign(a) != _sign(an) or _sign(v + 2.0 * zeta * a) != _sign(vn + 2.0 * zeta * an)
                 or band_mode(v, d1_[2], vd) != band_mode(vn, d4_[2], vd) or (t < t_tail <= t + dt))
        if event and not kept:
            _record(out, k, t, x, v, _sample(x, v, d1_[1], zeta, d1_[2], lw), (w0, w1, w2, w3, w4))
            k += 1
            w0 = w1 = w2 = w3 = w4 = 0.0
        w0 += d0
        w1 += d1
        w2 += d2
        w3 += d3
        if forced:
            w4 += d4
        x, v, a = xn, vn, an
        d1_ = d4_
        kept = False
        i += 1
        if event or i == n_total:
            _record(out, k, t0 + i * dt, x, v, _sample(x, v, d1_[1], zeta, d1_[2], lw), (w0, w1, w2, w3, w4))
            k += 1
            w0 = w1 = w2 = w3 = w4 = 0.0
            kept = True
    s[0], s[1], s[2], s[3], s[4], s[5], s[6] = x, v, w0, w1, w2, w3, w4
    s[N_STATE], s[N_STATE + 1] = a, 1.0 if kept else 0.0
    return k, i
