"""Steady-state results for many parameter points per call, parallel over the cores.

Each kernel takes per-point model and friction parameters and returns one
row of results per point: the swept quantities of the table in
:mod:`frictionflow.quantities`, in its order (positions ``R_*``) -- the
same quantities ``frictionflow simulate --json`` reports, computed by the
same section-record classifier (:mod:`.sections`).  The exact and adaptive
kernels stop a point early once its section values repeat (``rtol``,
``min_periods``) or, for the exact solver, once it is in a slip phase it can
never leave (the sliding equilibrium): the rest of the run would change
nothing.

The point kernels take records (module-level named tuples, typed by numba),
each unpacked once at the kernel's top:

==========  ================================================================
``Points``  the per-point inputs, row ``j`` of each array is point ``j``:
            its force record ``p`` (``(n, N_PARAMS)``), zeta, V_b, X0, X'0
``Judge``   how every point's section records are judged (the classifier's
            settings): rtol, min_periods, the fixed step h (0: adaptive
            steps), fixed_step (flag) and the section noise
``Ode``     the adaptive kernel's step control: rtol, atol, max_steps
==========  ================================================================

The per-point outputs are the rows of ``out`` (``(n, NR)``) and, for the
kernels ``with_room`` runs, the flags ``full``.  A record from Python costs
a kernel call about 0.5 us more than its fields would (:mod:`.records`):
once per piece of points, not per point.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .. import quantities as Q
from . import certificate, dopri, exact, rk4_batch
from . import sections as sec
from .friction import FD, slip_magnitude_of
from .layout import N_WORK
from .records import N_CONTACTS, N_STATE, new_events, new_samples, run_record
from .rk4 import step_count
from .threads import over_points

# The result row is the first NR entries of the table's layout, the one
# sections fills.  Positions by name; numba reads them as constants.
(
    R_KIND, R_PERIOD, R_P_DV, R_P_DF, R_P_FIN, R_R_C, R_R_F, R_P_BELT, R_P_HEAT, R_TR_B,
    R_X_MIN, R_X_MAX, R_V_MIN, R_V_MAX, R_STICK, R_RESID,
) = (Q.index(n) for n in (
    "kind", "period", "P_dv", "P_df", "P_fin", "R_c", "R_f", "P_belt", "P_heat", "TR_B",
    "X_min", "X_max", "V_min", "V_max", "stick_fraction", "energy_residual",
))
NR = Q.NR

Points = namedtuple("Points", "p zeta vb x0 v0")
Judge = namedtuple("Judge", "rtol min_periods h fixed_step noise")
Ode = namedtuple("Ode", "rtol atol max_steps")


@njit(cache=True)
def _not_settled(out):
    """The row of a point without a result."""
    out[:] = np.nan
    out[R_KIND] = sec.NOT_SETTLED


@njit(cache=True)
def _row(rec, tail, fin, p, zeta, vb, rtol, min_periods, h, fixed_step, noise, out):
    """A point's result row: ``diverged`` if its state left the float range, the equilibrium if the
    certificate proves it (:mod:`.certificate`), else what its section records say."""
    fd = p[FD]
    if not np.isfinite(fin[sec.A_E]):
        out[:] = np.nan
        out[R_KIND] = sec.DIVERGED
        return
    x_eq = math.copysign(slip_magnitude_of(p, abs(vb)), vb)
    x, v = fin[sec.A_XEND], fin[sec.A_VEND]
    # slipping with the belt at the end, closer to X* than V_b (no disc is larger): is it in the certified disc?
    if (vb - v) * vb > 0.0 and (x - x_eq) ** 2 + v * v < vb * vb:
        r = certificate.certified_radius(p, zeta, vb)
        if certificate.inside(x_eq, vb, r, fin[sec.A_XEND], fin[sec.A_VEND]):
            whole = sec.averages(fin[sec.A_W0], fin[sec.A_W1], fin[sec.A_W2], fin[sec.A_W3], 0.0, fin[sec.A_E0],
                                 fin[sec.A_E], max(fin[sec.A_T], 1e-300))
            sec.put(out, sec.equilibrium_row(x_eq, vb, fd, 0.0, whole[sec.RESID]))
            return
    scale = sec.scale_of(rec, tail, vb, fd)
    cls = sec.classify(rec, tail, scale, rtol, min_periods, h, fixed_step, noise * scale)
    sec.put(out, sec.window_summary(rec, tail, fin, cls, fd, vb))


@njit(cache=True)
def _classify_samples(samples, k, p, zeta, vb, judge, out):
    """A point's result row from the first ``k`` of its ``samples`` (:class:`.records.Samples`)."""
    rtol, min_periods, h, fixed_step, noise = judge
    t, y, fc, modes, work = samples
    t, x, v, mode, work = t[:k], y[0, :k], y[1, :k], modes[0, :k], work[:k]
    t_tail = sec.tail_start(t[0], t[-1])
    rec, tail, fin = sec.records_from_samples(t, x, v, mode, work, zeta, t_tail)
    if rec.shape[0] > sec.MAX_RECORDS:
        rec = rec[rec.shape[0] - sec.MAX_RECORDS :].copy()
    _row(rec, tail, fin, p, zeta, vb, rtol, min_periods, h, fixed_step, noise, out)


@njit(cache=True)
def _buffers(cap):
    """One point's (samples, events) records (:mod:`.records`; events are not kept: one slot, never read)."""
    return (new_samples(cap, N_STATE, N_CONTACTS),
            new_events(1))


def with_room(kernel, n: int, cap: int, *args) -> None:
    """Run a point kernel over ``n`` points with room for ``cap`` samples each, then again, with four
    times the room, over the points that filled it -- the one retry loop of the batched kernels.

    ``kernel(j0, j1, todo, cap, full, *args)`` handles the points ``todo[j0:j1]``
    and sets ``full[j]`` for each point ``j`` whose samples did not fit.
    """
    todo = np.arange(n)
    full = np.zeros(n, dtype=np.bool_)
    while todo.size:
        over_points(kernel, todo.size, todo, cap, full, *args)
        todo = todo[full[todo]]
        cap *= 4


def exact_points(p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray, t_end: float,
                 rtol: float, min_periods: int, noise: float, out: np.ndarray, cap: int | None = None) -> None:
    """Exact solver for every point (rows of ``p``: friction kernel parameters), parallel over the cores.

    ``cap``: the samples each point has room for at first (default: 16 per 2 pi).
    """
    cap = int(16.0 * t_end / (2.0 * math.pi)) + 64 if cap is None else cap
    judge = Judge(rtol, min_periods, 0.0, False, noise)
    with_room(_exact_points, len(zeta), cap, Points(p, zeta, vb, x0, v0), t_end, judge, out, True)


# Flags arrive from Python (arguments, Judge's fixed_step), never as constants written in a kernel: numba would
# compile the callees once more for each constant (a literal type), seconds on a fresh cache.
@njit(cache=True, nogil=True)
def _exact_points(j0, j1, todo, cap, full, points, t_end, judge, out, stop_early):
    p, zeta, vb, x0, v0 = points
    rtol, min_periods = judge.rtol, judge.min_periods
    for j in todo[j0:j1]:
        samples, events = _buffers(cap)
        t, y, work = samples.t, samples.y, samples.work
        t_mode = np.zeros(1, dtype=np.int64)
        # unforced only: sweeps send forced points through the façade (stroboscopic analysis)
        # (every argument positional and typed as from the façades: one compiled builder; no bare int constant)
        run = run_record((x0[j], v0[j]), t_end, zeta[j], vb[j], sec.tail_start(0.0, t_end), 0.0, (0.0, 0.0, np.int64(0)),
                         (stop_early, stop_early, rtol, min_periods), (0.0, 0.0))
        # no replication, the periodic stop (np.bool_: plain booleans, typed as the façade's call, one compiled run)
        k, ne, status, t_term, t_stop = exact.run(run, p[j], samples, events, t_mode, np.bool_(False), np.bool_(True))
        full[j] = status == exact.FULL
        if full[j]:
            continue
        fd = p[j, FD]
        if status == exact.STUCK:
            _not_settled(out[j])
        elif t_term >= 0.0 and zeta[j] > 0.0 and exact.settles_analytically(t_mode[0], y[1, k - 1]):
            # a final phase: a slip decays onto X* = F(V_b), sliding; a stick rests where it holds, stuck for
            # good (the stick fraction simulate's window gives it); the residual is the run's
            tot = np.zeros(N_WORK)
            for i in range(k):  # (a loop: sum(axis=0) compiles its own implementation)
                for q in range(N_WORK):
                    tot[q] += work[i, q]
            a = sec.averages(tot[0], tot[1], tot[2], tot[3], 0.0, 0.5 * (x0[j] ** 2 + v0[j] ** 2),
                             0.5 * (y[0, k - 1] ** 2 + y[1, k - 1] ** 2), max(t[k - 1], 1e-300))
            stuck = t_mode[0] == 0
            x_eq = y[0, k - 1] if stuck else t_mode[0] * slip_magnitude_of(p[j], abs(vb[j]))
            sec.put(out[j], sec.equilibrium_row(x_eq, vb[j], fd, 1.0 if stuck else 0.0, a[sec.RESID]))
        else:
            _classify_samples(samples, k, p[j], zeta[j], vb[j], judge, out[j])


def adaptive_points(p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray, t_end: float,
                    ode: Ode, rtol: float, min_periods: int, noise: float, out: np.ndarray,
                    cap: int | None = None) -> None:
    """Adaptive Dormand-Prince for every point (built-in slip laws), parallel over the cores.

    ``ode``: the step control, an ``Ode`` (rtol, atol, max_steps).
    ``cap``: the samples each point has room for at first (default: about 64 per time unit up to
    t_end, at most 2^15, 2.4 MB a thread: a point that fills it runs again from the start, so the
    room is given once -- each thread reuses its buffers from point to point).
    """
    cap = min(int(64.0 * t_end) + 256, 1 << 15) if cap is None else cap
    with_room(_adaptive_points, len(zeta), cap, Points(p, zeta, vb, x0, v0), t_end, Ode(*ode),
              Judge(rtol, min_periods, 0.0, False, noise), out)


@njit(cache=True)
def _same_radius(p, zeta, vb, i, j):
    """Do points ``i`` and ``j`` have the same law, zeta and V_b (so the same certified radius)?"""
    if zeta[i] != zeta[j] or vb[i] != vb[j]:
        return False
    for q in range(p.shape[1]):
        if p[i, q] != p[j, q]:
            return False
    return True


@njit(cache=True, nogil=True)
def _adaptive_points(j0, j1, todo, cap, full, points, t_end, ode, judge, out):
    p, zeta, vb, x0, v0 = points
    ode_rtol, ode_atol, max_steps = ode
    rtol, min_periods = judge.rtol, judge.min_periods
    samples, events = _buffers(cap)  # each run writes from the start and is read up to its own count
    # the point whose certified radius r is: a basin grid shares one (the disc is the same search);
    # not a literal, so that _same_radius compiles once
    last = np.int64(-1)
    r = 0.0
    for j in todo[j0:j1]:
        if last < 0 or not _same_radius(p, zeta, vb, last, j):
            r = certificate.certified_radius(p[j], zeta[j], vb[j])
            last = j
        # stop once the end is known: the certified disc, or repeating sections (as the classifier judges them)
        run = run_record((x0[j], v0[j]), t_end, zeta[j], vb[j], sec.tail_start(0.0, t_end), 0.0, (ode_rtol, ode_atol, max_steps),
                         (np.bool_(False), np.bool_(False), rtol, min_periods),
                         (r, math.copysign(slip_magnitude_of(p[j], abs(vb[j])), vb[j])))
        # unforced only: sweeps send forced points through the façade (stroboscopic analysis)
        k, ne, status, t_stop, h = dopri.run_unforced(run, p[j], samples, events)
        full[j] = status == dopri.FULL
        if full[j]:
            continue
        if status != dopri.OK:
            _not_settled(out[j])
        else:
            _classify_samples(samples, k, p[j], zeta[j], vb[j], judge, out[j])


@njit(cache=True, nogil=True)
def _rk4_rows(j0, j1, runs, points, judge, out):
    """Rows ``j0 .. j1-1``: ``runs`` = (rec, nrec, tail, fin) of :func:`.rk4_batch.run_batch`."""
    rec, nrec, tail, fin = runs
    p, zeta, vb, x0, v0 = points
    rtol, min_periods, dt, fixed_step, noise = judge
    for j in range(j0, j1):
        _row(rk4_batch.unroll(rec[j], nrec[j]), tail[j], fin[j], p[j], zeta[j], vb[j], rtol, min_periods, dt, fixed_step, noise,
             out[j])


def rk4_points(law: int, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray, t_end: float,
               dt: float, rtol: float, min_periods: int, noise: float, out: np.ndarray) -> None:
    """Batched fixed-step RK4 (lanes in lock step, SIMD) for every point."""
    steps = step_count(t_end, dt)
    rk4_batch.warm_up()
    runs = rk4_batch.run_batch(law, zeta, vb, p, x0, v0, dt, steps, sec.tail_start(0.0, steps * dt))
    over_points(_rk4_rows, len(zeta), runs, Points(p, zeta, vb, x0, v0), Judge(rtol, min_periods, dt, True, noise), out)
