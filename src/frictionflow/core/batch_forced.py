"""Forced sweep points (F_ex > 0) on the exact solver, many per call, parallel over the cores.

Each point runs :func:`.exact.run_forced` with the settings ``simulate`` gives
it, into buffers the compiled classifier reads at once: the stroboscopic test
of :mod:`frictionflow.analysis.forced` ported line by line (:mod:`.strobe`),
and the row ``analyze`` reports over its window.  The same run and the same
arithmetic: every value is the one ``analyze(simulate(...))`` gives, bit for
bit.  There is no early stop: the window ``analyze`` averages over spans the
repetitions up to the run's end, which a shorter run would not have.

A point whose section repeats is done in the kernel.  One whose section does
not repeat has its row (the window is then the tail) but not its kind, which
the largest Lyapunov exponent decides (chaotic, quasi-periodic or not
settled); that exponent's tangent run (:func:`.tangent.run_until`, with the
settings of ``forced.largest_exponent``) runs in a second pass over those
points, in threads too.  What the kernel cannot judge as the façade does --
a stalled run (the façade raises), a section time without a sample, a state
that left the float range, an empty window -- is flagged for the façade.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .. import quantities as Q
from . import exact, strobe, tangent
from . import sections as sec
from .batch import _buffers, with_room
from .layout import FD, FEX, OMEGA
from .records import run_record
from .threads import over_points

# what the kernel leaves per point besides its row: ``aux[j, *]``
A_STATUS, A_X, A_V, A_REVISITS = range(4)
N_AUX = 4
# a point's own values: ``point[j, *]`` (its force record is ``p[j]``)
P_X0, P_V0, P_ZETA, P_VB = range(4)
N_POINT = 4
# the settings every point shares: a float64 record (min_periods stored as a float, read with int())
S_T_END, S_DENSE_DT, S_RTOL, S_MIN_PERIODS, S_NOISE = range(5)
N_SETTINGS = 5
#: A_STATUS: the row is complete; the kind needs the Lyapunov exponent; the façade must run the point
DONE, LYAPUNOV, FACADE = 0, 1, 2
PERIODIC, NOT_SETTLED, QUASI_PERIODIC, CHAOTIC = (Q.KINDS.index(k) for k in (
    "periodic", "not_settled", "quasi_periodic", "chaotic"))


@njit(cache=True)
def _section_values(x, v, idx, first):
    """(X, X') at the section samples ``idx[first:]``."""
    n = len(idx) - first
    xs, vs = np.empty(n), np.empty(n)
    for i in range(n):
        xs[i], vs[i] = x[idx[first + i]], v[idx[first + i]]
    return xs, vs


@njit(cache=True)
def _judge(samples, k, p, zeta, vb, settings, out, aux):
    """The forced run in ``samples[:k]`` classified on its stroboscopic section, its row in ``out``.

    As ``forced.classify_forced`` then ``analyze``: the section's tail is its
    second half; periodic with the smallest multiple m that repeats, over
    the whole repetitions up to the last section sample; else the tail is
    the window and the kind is left to the Lyapunov pass (``aux``).
    """
    t, x, v = samples.t, samples.y[0], samples.y[1]
    rtol, min_periods, noise = settings[S_RTOL], int(settings[S_MIN_PERIODS]), settings[S_NOISE]
    if not (math.isfinite(x[k - 1]) and math.isfinite(v[k - 1])):
        aux[A_STATUS] = FACADE  # diverged: every number is NaN there, the window from the first bad sample
        return
    period = 2.0 * math.pi / p[OMEGA]
    idx = strobe.section_indices(t, k, period)
    if len(idx) < strobe.section_count(t[k - 1], period):
        aux[A_STATUS] = FACADE  # a section time without a sample: the façade raises
        return
    n = len(idx)
    xs, vs = _section_values(x, v, idx, n // 2)
    scale = max(max(np.ptp(xs), np.ptp(vs)), max(max(p[FEX], abs(vb)), max(p[FD], 1e-300)))
    m, reps = strobe.repeat_multiple(xs, vs, max(rtol, noise) * scale, min_periods)
    first = idx[n - 1 - m * reps] if m else idx[n // 2]
    last = idx[n - 1]
    if not t[first] < t[last]:
        aux[A_STATUS] = FACADE  # an empty window: the façade refuses it
        return
    strobe.window_row(samples, k, t[first], t[last], zeta, p[FEX], out)
    out[strobe.R_KIND] = PERIODIC if m else NOT_SETTLED
    out[strobe.R_PERIOD] = m * period if m else np.nan
    aux[A_STATUS] = DONE if m else LYAPUNOV
    aux[A_X], aux[A_V] = x[last], v[last]
    torus = not m and strobe.revisits(xs, vs, strobe.REVISIT_SHARE * scale)
    if torus:
        points = np.empty((2, len(xs)))
        points[0], points[1] = xs, vs
        torus = not strobe.closing_in(points)
    aux[A_REVISITS] = 1.0 if torus else 0.0


# Flags arrive as arguments from Python, never as constants written in a kernel: numba would compile the
# callees once more for each constant (a literal type), seconds on a fresh cache.
@njit(cache=True, nogil=True)
def _forced_points(j0, j1, todo, cap, full, p, point, settings, out, aux, off):
    # one set of buffers for the piece: a run writes every sample before anything reads it
    samples, events = _buffers(cap)
    t_mode = np.zeros(1, dtype=np.int64)
    t_end = settings[S_T_END]
    t_tail = sec.tail_start(0.0, t_end)
    for j in todo[j0:j1]:
        x0, v0, zeta, vb = point[j, P_X0], point[j, P_V0], point[j, P_ZETA], point[j, P_VB]
        # the run record simulate's exact façade builds (run_forced reads the state, span, tail and dense grid;
        # every argument typed as the façade's: one compiled builder)
        run = run_record((x0, v0), t_end, zeta, vb, t_tail, settings[S_DENSE_DT], (0.0, 0.0, np.int64(0)),
                         (off, off, 0.0, int(settings[S_MIN_PERIODS])), (0.0, 0.0))
        k, ne, status, t_term, t_stop = exact.run_forced(run, p[j], samples, events, t_mode)
        full[j] = status == exact.FULL
        if full[j]:
            continue
        if status != exact.DONE:
            aux[j, A_STATUS] = FACADE  # stalled in zero-length phases: the façade raises, with its hint
            continue
        _judge(samples, k, p[j], zeta, vb, settings, out[j], aux[j])


@njit(cache=True, nogil=True)
def _tangent_points(j0, j1, start, zeta, vb, p, block, counts, run, found):
    """The tangent runs of ``forced.largest_exponent`` for points j0..j1: ``found[j]`` = (status, s1, s2, spread,
    averaged blocks done).

    ``start[j]``: the state at the last section sample; ``counts[j]``: the
    transient and averaged blocks; ``run``: (RK4 steps per block, its stop
    rule: :func:`.tangent.run_until`); spread: the range of the running
    estimate of lambda_1 over the second half of the blocks done (NaN unless finite).
    """
    steps, stop = run
    for j in range(j0, j1):
        n_tr, n_bl = counts[j, 0], counts[j, 1]
        strobe_states = np.zeros((n_tr + n_bl, 3))
        est = np.full((n_bl, 2), np.nan)
        switches = np.zeros(tangent.N_COUNTS, dtype=np.int64)
        status, s1, s2, n_done = tangent.run_until(start[j, 0], start[j, 1], zeta[j], vb[j], p[j], block[j], steps,
                                                   (n_tr, n_bl), stop, strobe_states, est, switches)
        lo, hi, finite = np.inf, -np.inf, True
        for i in range(n_done // 2, n_done):
            e = est[i, 0]
            finite = finite and math.isfinite(e)
            lo, hi = min(lo, e), max(hi, e)
        found[j, 0], found[j, 1], found[j, 2], found[j, 4] = status, s1, s2, n_done
        found[j, 3] = hi - lo if finite else np.nan


def forced_points(p, zeta, vb, x0, v0, t_end, rtol, min_periods, noise, out, *, dense_dt=0.0,
                  lyapunov=True) -> np.ndarray:
    """Rows (``out``) of forced points (rows of ``p``: force records with F_ex > 0) on the exact solver.

    ``lyapunov``: whether the law has the tangent kernel (Coulomb's stick
    rule; ``forced.largest_exponent`` returns None otherwise, and a
    non-repeating section is then ``not_settled``).  Returns a mask of the
    points left to the façade, whose rows are not filled.
    """
    n = len(zeta)
    aux = np.zeros((n, N_AUX))
    point = np.empty((n, N_POINT))
    point[:, P_X0], point[:, P_V0], point[:, P_ZETA], point[:, P_VB] = x0, v0, zeta, vb
    settings = np.empty(N_SETTINGS)
    settings[S_T_END], settings[S_DENSE_DT], settings[S_RTOL], settings[S_MIN_PERIODS], settings[S_NOISE] = (
        t_end, dense_dt, rtol, min_periods, noise)
    with_room(_forced_points, n, room(p, t_end, dense_dt), p, point, settings, out, aux, False)
    todo = np.flatnonzero(aux[:, A_STATUS] == LYAPUNOV)
    if todo.size:
        out[todo, strobe.R_KIND] = _kinds(p[todo], zeta[todo], vb[todo], aux[todo]) if lyapunov else NOT_SETTLED
    return aux[:, A_STATUS] == FACADE


def room(p: np.ndarray, t_end: float, dense_dt: float) -> int:
    """The samples each point has room for at first: simulate's estimate at the highest Omega of ``p``.

    A point that fills it runs again with more (``with_room``): the same
    result at the cost of a second run, so the dense grid's samples are
    counted in too.
    """
    om = float(np.max(p[:, OMEGA])) if len(p) else 1.0
    dense = int(t_end / dense_dt) + 2 if dense_dt else 0
    forced = int(t_end * om / (2 * math.pi)) + int(8 * om * t_end / math.pi)
    return int(16 * t_end / (2 * math.pi)) + 64 + dense + forced


def _kinds(p, zeta, vb, aux) -> np.ndarray:
    """The kinds of points whose section does not repeat, decided as ``forced.classify_forced`` decides them."""
    n = len(zeta)
    block = 2.0 * math.pi / p[:, OMEGA]  # the forcing period, renormalised once per period
    counts = np.empty((n, 2), dtype=np.int64)
    for j, b in enumerate(block.tolist()):  # lyapunov_exponents' block counts, in its arithmetic
        t_transient, t_end = strobe.LYAPUNOV_TRANSIENT * b, (strobe.LYAPUNOV_TRANSIENT + strobe.LYAPUNOV_PERIODS) * b
        n_tr = math.ceil(t_transient / b - 1e-9)
        counts[j] = n_tr, max(1, math.ceil((t_end - n_tr * b) / b - 1e-9))
    found = np.empty((n, 5))
    start = np.ascontiguousarray(aux[:, [A_X, A_V]])
    stop = tuple(int(c) if i < 2 else float(c) for i, c in enumerate(strobe.LYAPUNOV_STOP))
    # a piece per point: a tangent run costs tens of milliseconds, so a thread left with a piece of several at
    # the end would keep the other idle that long (a piece's dispatch costs tens of microseconds)
    over_points(_tangent_points, n, start, zeta, vb, np.ascontiguousarray(p), block, counts,
                (strobe.LYAPUNOV_STEPS, stop), found, per_thread=max(1, n))
    kinds = np.full(n, NOT_SETTLED, dtype=float)
    for j in range(n):
        status, s1, s2, spread, n_done = found[j].tolist()
        if status != tangent.OK:
            continue  # the tangent run could not cross a switch: no exponent, not settled
        elapsed = int(n_done) * float(block[j])
        lam = s2 / elapsed if s2 / elapsed > s1 / elapsed else s1 / elapsed  # the larger (rounding may swap them)
        spread = max(spread, strobe.LYAPUNOV_SPREAD_FLOOR)  # (NaN stays NaN: Python's max keeps its first argument)
        if lam > spread:
            kinds[j] = CHAOTIC
        elif abs(lam) <= spread and aux[j, A_REVISITS] != 0.0:
            kinds[j] = QUASI_PERIODIC
    return kinds
