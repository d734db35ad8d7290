"""The stroboscopic steady-state test of a forced run, compiled: what the batched forced sweep judges with.

:mod:`frictionflow.analysis.forced` judges a forced run on the states at the
stroboscopic times k 2 pi / Omega; :mod:`.batch_forced` judges many runs in
compiled threads and must give the same answer.  These are its pieces; the
window values are line-by-line ports of the numpy they mirror, with the same
floating-point operations in the same order (so the results are the same
bits, not only close):

* :func:`section_indices`, :func:`repeat_multiple`, :func:`revisits`,
  :func:`closing_in` -- the section and its repetition and torus tests, which :mod:`frictionflow.analysis.forced`
  calls too (stated once, here);
* :func:`window_row` -- what :func:`frictionflow.analysis.analyze` reports over
  a window that starts and ends on samples: ``power_flow`` (its sums of the
  work integrals: numpy's axis-0 sum, sequential), ``transmissibility``,
  ``amplitude`` and ``stick_fraction`` (numpy's 1-D sum: pairwise,
  :func:`pairwise_sum`).

The constants of the test live here, so that both paths read one value.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .. import quantities as Q
from . import sections as sec
from .layout import N_WORK

#: the longest subharmonic looked for (in forcing periods)
MAX_MULTIPLE = 16
#: an m-cycle whose last repetition is d-periodic to this many tolerances, for a divisor d < m of m, is a d-cycle
#: still converging: a multiplier mu near a root of unity shrinks P_{k+m} - P_k (as mu^m - 1) below the tolerance
#: before P_{k+d} - P_k (mu^d - 1; mu = 0.94i: 6 to 8 times), where a true m-cycle's points stay apart by its size
SUBCYCLE_SPREAD = 100.0
#: how far from tau_k a sample may be and still be the section's (relative to the forcing period)
SECTION_MATCH = 1e-9
#: forcing periods the Lyapunov exponent is averaged over, after a short transient, when the section does not repeat
LYAPUNOV_PERIODS = 400
LYAPUNOV_TRANSIENT = 20
#: RK4 steps per forcing period of the Lyapunov exponent's tangent run
LYAPUNOV_STEPS = 256
#: the smallest uncertainty of a finite run's exponent: below it an exponent cannot be told from 0
LYAPUNOV_SPREAD_FLOOR = 1e-4
#: the tangent run ends once lambda_1 < -2 max(spread, floor), checked after 60, 80, 100, ... averaged periods
#: (:func:`frictionflow.core.tangent.run_until`: first, every, factor, floor): the kind is then not_settled
#: whatever the remaining periods give
LYAPUNOV_STOP = (60, 20, 2.0, LYAPUNOV_SPREAD_FLOOR)
#: a non-repeating section is quasi-periodic only if its second half revisits the first to this share of its scale
REVISIT_SHARE = 0.05
#: ... and does not close in on a point: its quarters' extents fall, the last below this share of the first's
CONTRACTION = 0.9
#: ... nor on a cycle of m points (m up to a quarter of the section, at most CYCLE_MAX): the largest and the mean
#: m-step difference |P_{k+m} - P_k| of each quarter fall, the last below CYCLE_FALL of the first's (a torus's
#: differences are one function of its angle, which each quarter samples alike)
CYCLE_MAX = 1024
CYCLE_FALL = 0.5
#: ... each quarter's below CYCLE_STEP of the one before (a torus whose rotation is within ~1e-4 of p/m drifts
#: its m-step differences once, then holds them: a fall that stops is no convergence)
CYCLE_STEP = 0.9

# Positions in the result row (the quantities table's first NR entries).
R_KIND, R_PERIOD, R_TR_B, R_X_MIN, R_X_MAX, R_V_MIN, R_V_MAX, R_STICK = (Q.index(n) for n in (
    "kind", "period", "TR_B", "X_min", "X_max", "V_min", "V_max", "stick_fraction"))
#: numpy's pairwise summation: below this many terms a block is summed with 8 accumulators
PW_BLOCKSIZE = 128


@njit(cache=True)
def first_at_or_after(t, k, value):
    """The first index i < k with t[i] >= value, or k (numpy's ``searchsorted``, side left)."""
    lo, hi = 0, k
    while lo < hi:
        mid = (lo + hi) >> 1
        if t[mid] < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def section_count(t_last, period):
    """How many section times tau_j = j ``period`` a run to ``t_last`` has (j = 0 included)."""
    return int(math.floor(t_last / period * (1 + 1e-12))) + 1


@njit(cache=True)
def section_indices(t, k, period):
    """Indices of the samples ``t[:k]`` at tau_j = j ``period`` (j = 0, 1, ...), up to the first section
    time without a sample (fewer than :func:`section_count` then: the façade raises, naming it)."""
    n = section_count(t[k - 1], period)
    match = SECTION_MATCH * period
    idx = np.empty(n, dtype=np.int64)
    for j in range(n):
        time = j * period
        i = min(max(first_at_or_after(t, k, time - match), 0), k - 1)
        if not abs(t[i] - time) <= match * max(1.0, float(j)):
            return idx[:j]
        idx[j] = i
    return idx


@njit(cache=True)
def _mismatch(x, v, i, m, tol):
    """P_{i+m} differs from P_i by more than ``tol`` (np.maximum of the two differences: NaN is no mismatch)."""
    dx = abs(x[i + m] - x[i])
    dv = abs(v[i + m] - v[i])
    if math.isnan(dx) or math.isnan(dv):
        return False
    return dx > tol or dv > tol


@njit(cache=True)
def repeat_multiple(x, v, tol, min_periods, max_multiple=MAX_MULTIPLE):
    """(m, repetitions): the smallest m <= ``max_multiple`` whose last ``min_periods`` repetitions match to
    ``tol``; (0, 0) if none, or if that m's last repetition is a shorter cycle still converging
    (:data:`SUBCYCLE_SPREAD`)."""
    n = len(x)
    for m in range(1, max_multiple + 1):
        if n < (min_periods + 1) * m:
            break
        run = 0  # trailing matches P_{i+m} = P_i, counted back from the end
        for i in range(n - m - 1, -1, -1):
            if _mismatch(x, v, i, m, tol):
                break
            run += 1
        if run >= min_periods * m:
            if converging_subcycle(x, v, m, SUBCYCLE_SPREAD * tol):
                return 0, 0
            return m, run // m
    return 0, 0


@njit(cache=True)
def converging_subcycle(x, v, m, tol):
    """Whether the last m section points repeat after a proper divisor d of m to ``tol``: P_{i+d} = P_i there."""
    n = len(x)
    for d in range(1, m):
        if m % d:
            continue
        same = True
        for i in range(n - m, n - d):
            if _mismatch(x, v, i, d, tol):
                same = False
                break
        if same:
            return True
    return False


@njit(cache=True)
def revisits(x, v, tol):
    """Whether every point of the second half lies within ``tol`` of some point of the first half (finite values)."""
    h = len(x) // 2
    if h < 8:
        return False
    for b in range(h, len(x)):
        near = np.inf
        for a in range(h):
            near = min(near, max(abs(x[b] - x[a]), abs(v[b] - v[a])))
        if not near <= tol:
            return False
    return True


@njit(cache=True)
def contracting(points):
    """Whether the section's points (the columns of ``points``, one row per component, in time order) close in
    on a point: the extents (a component's largest range) of its four quarters fall, each below the one before,
    the last below :data:`CONTRACTION` of the first.  A torus's quarters cover one closed curve; a slowly
    attracting cycle's section spirals in (its multipliers near the unit circle: the exponent alone, within its
    uncertainty of 0, cannot tell it from a torus).  At least 4 points a quarter."""
    q = points.shape[1] // 4
    if q < 4:
        return False
    before = np.inf
    first = 0.0
    for j in range(4):
        extent = 0.0
        for c in range(points.shape[0]):
            lo, hi = np.inf, -np.inf
            for i in range(j * q, (j + 1) * q):
                lo, hi = min(lo, points[c, i]), max(hi, points[c, i])
            extent = max(extent, hi - lo)
        if not extent < before:
            return False
        if j == 0:
            first = extent
        before = extent
    return before < CONTRACTION * first


@njit(cache=True)
def _quarter_differences(points, m, q, j):
    """(largest, mean) m-step difference |P_{i+m} - P_i| (max-norm) over quarter ``j`` (q points) of ``points``."""
    largest, total = 0.0, 0.0
    for i in range(j * q, (j + 1) * q):
        d = 0.0
        for c in range(points.shape[0]):
            d = max(d, abs(points[c, i + m] - points[c, i]))
        largest = max(largest, d)
        total += d
    return largest, total / q


@njit(cache=True)
def _differences_fall(points, m, q):
    """Whether the largest and the mean m-step differences of the four quarters both fall, each below
    :data:`CYCLE_STEP` of the quarter's before, the last below :data:`CYCLE_FALL` of the first's."""
    first_max, first_mean = _quarter_differences(points, m, q, 0)
    last_max, last_mean = first_max, first_mean
    for j in range(1, 4):
        big, mean = _quarter_differences(points, m, q, j)
        if not (big < CYCLE_STEP * last_max and mean < CYCLE_STEP * last_mean):
            return False
        last_max, last_mean = big, mean
    return last_max < CYCLE_FALL * first_max and last_mean < CYCLE_FALL * first_mean


@njit(cache=True)
def converging_cycle(points):
    """Whether the section's points (columns, in time order) close in on a cycle of m points, for some m up to
    a quarter of them (at most :data:`CYCLE_MAX`): the m-step differences |P_{k+m} - P_k| of each quarter fall,
    their largest and their mean alike (:func:`_differences_fall`).  A slowly attracting long cycle (a phase
    lock of hundreds of forcing periods) revisits like a torus, with an exponent within its uncertainty of 0;
    only its returns shrinking tell it apart.  A torus's differences are one function of its angle, which
    each quarter samples alike: a narrow peak may be missed by a quarter, its mean not.  At least 16 points a
    quarter."""
    n = points.shape[1]
    for m in range(1, min((n - 1) // 4, CYCLE_MAX) + 1):
        q = (n - m) // 4
        if q < 16:
            return False
        if _differences_fall(points, m, q):
            return True
    return False


@njit(cache=True)
def closing_in(points):
    """Whether the section closes in on a point (:func:`contracting`) or on a cycle (:func:`converging_cycle`):
    a slowly attracting cycle, not a torus."""
    return contracting(points) or converging_cycle(points)


@njit(cache=True)
def _block_sum(a, lo, n):
    """numpy's sum of a block of at most :data:`PW_BLOCKSIZE` terms: 8 accumulators, then the rest in order."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = 8
    while i < n - n % 8:
        j = lo + i
        r0 += a[j]
        r1 += a[j + 1]
        r2 += a[j + 2]
        r3 += a[j + 3]
        r4 += a[j + 4]
        r5 += a[j + 5]
        r6 += a[j + 6]
        r7 += a[j + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[lo + i]
        i += 1
    return res


@njit(cache=True)
def pairwise_sum(a, lo, n):
    """numpy's sum of ``a[lo:lo + n]``, the same bits as ``np.sum``: halves (the first a multiple of 8) summed
    apart, down to blocks (:func:`_block_sum`).

    numpy recurses; this walks the same tree with a stack (a recursive kernel
    loaded from numba's cache crashes its caller).  Tasks: (start, length) to
    sum, or length -1: add the last two sums.
    """
    task_lo = np.empty(192, dtype=np.int64)
    task_n = np.empty(192, dtype=np.int64)
    sums = np.empty(64)
    nt, ns = 1, 0
    task_lo[0], task_n[0] = lo, n
    while nt:
        nt -= 1
        l, m = task_lo[nt], task_n[nt]
        if m < 0:  # both halves done: left + right
            ns -= 1
            sums[ns - 1] = sums[ns - 1] + sums[ns]
        elif m <= PW_BLOCKSIZE:
            sums[ns] = _block_sum(a, l, m)
            ns += 1
        else:  # the combination, then the right half, then the left (a stack: the left is summed first)
            m2 = m // 2
            m2 -= m2 % 8
            task_lo[nt], task_n[nt] = 0, -1
            task_lo[nt + 1], task_n[nt + 1] = l + m2, m - m2
            task_lo[nt + 2], task_n[nt + 2] = l, m2
            nt += 3
    return sums[0]


@njit(cache=True)
def stick_fraction(t, mode, i0, i1):
    """Share of samples i0..i1 spent sticking, time-weighted (``analysis.steady_state.stick_fraction``)."""
    if i1 <= i0:
        return 1.0 if mode[i0] == 0 else 0.0
    dt = np.empty(i1 - i0)
    held = np.empty(i1 - i0)
    for i in range(i0, i1):
        dt[i - i0] = t[i + 1] - t[i]
        held[i - i0] = dt[i - i0] * (1.0 if mode[i] == 0 else 0.0)
    return pairwise_sum(held, 0, i1 - i0) / pairwise_sum(dt, 0, i1 - i0)


@njit(cache=True)
def window_row(samples, k, t0, t1, zeta, fex, out):
    """Fill ``out`` (a result row) with what ``analyze`` reports over the window (t0, t1) of sample times.

    The averages from the work integrals of the samples after t0 up to t1 and
    K + U at both ends; TR_B, the extremes and the stick fraction over the
    samples t0..t1.  ``kind`` and ``period`` are the caller's.
    """
    t, y, fc, modes, work = samples
    x, v, mode = y[0], y[1], modes[0]
    i0 = first_at_or_after(t, k, t0)
    i1 = first_at_or_after(t, k, t1)
    dw = np.zeros(N_WORK)
    for i in range(i0 + 1, i1 + 1):  # row by row, as numpy sums axis 0
        for q in range(N_WORK):
            dw[q] += work[i, q]
    e0 = 0.5 * (v[i0] * v[i0]) + 0.5 * (x[i0] * x[i0])
    e1 = 0.5 * (v[i1] * v[i1]) + 0.5 * (x[i1] * x[i1])
    sec.put(out, sec.averages(dw[0], dw[1], dw[2], dw[3], dw[4], e0, e1, t1 - t0))
    two_zeta = 2.0 * zeta
    fmax, xmin, xmax, vmin, vmax = -np.inf, np.inf, -np.inf, np.inf, -np.inf
    for i in range(i0, i1 + 1):
        fmax = max(fmax, abs(x[i] + two_zeta * v[i]))
        xmin, xmax = min(xmin, x[i]), max(xmax, x[i])
        vmin, vmax = min(vmin, v[i]), max(vmax, v[i])
    out[R_TR_B] = fmax / fex
    out[R_X_MIN], out[R_X_MAX], out[R_V_MIN], out[R_V_MAX] = xmin, xmax, vmin, vmax
    out[R_STICK] = stick_fraction(t, mode, i0, i1)
