"""Section records: what the steady-state classifier needs from a run.

Every run -- a sampled trajectory or a lane of a batched kernel that keeps
no samples -- is reduced to the same records, one per downward crossing of
the section X' = 0 (a maximum of X), each with the aggregates of the period
that ends there.  :func:`classify` then decides periodic / equilibrium /
not settled on these records alone, so that every solver and every path
(single run, batched sweep) is judged by one piece of code.

Record fields (``rec[i, F]``):

=========  ============================================================
T          crossing time (X' interpolated linearly between samples)
X          X at the crossing (cubic Hermite between samples)
TS         time of the first sample after the crossing: windows start
           and end on samples, where the work integrals are exact
ES         K + U at that sample
W0..W3     W_dv, W_fin, W_fout, W_heat over the period that ends there
VMIN..FMAX extremes of X' and |X + 2 zeta X'| over the period's samples
STICK      time spent sticking during the period
LO         X at the upward crossing (the minimum) inside the period, or NaN
=========  ============================================================

The extremes of X need no aggregates: they are the section values X (maxima)
and LO (minima), interpolated between samples.

The tail (the last 10 % of the run, at least 4 pi) has its own aggregates,
used for the equilibrium test; ``fin`` holds the run's last sample.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .. import quantities as Q
from .hermite import hermite

T, X, TS, ES, W0, W1, W2, W3, VMIN, VMAX, FMAX, STICK, LO = range(13)
NF = 13
# tail / final records: time and energy at the first tail sample (or the
# final sample); for the tail, its work integrals and extremes
A_T, A_E, A_W0, A_W1, A_W2, A_W3, A_XMIN, A_XMAX, A_VMIN, A_VMAX, A_FMAX, A_STICK, A_E0, A_XEND, A_VEND = range(15)
NA = 15  # fin: A_W* hold the whole run's work integrals, A_E0 its initial K + U, A_XEND/A_VEND its final state

#: records kept per run: windows span at most MAX_RECORDS - 1 periods
MAX_RECORDS = 32

PERIODIC, EQUILIBRIUM, NOT_SETTLED, DIVERGED = (Q.KINDS.index(k) for k in ("periodic", "equilibrium", "not_settled", "diverged"))
HEAD_NONE, HEAD_EQUILIBRIUM, HEAD_PERIODIC, HEAD_GROWING = 0, 1, 2, 3
#: a limit cycle is named as the heading only when it lies within this many times the last three records'
#: change of the last amplitude (a geometric approach with ratio r per record: r^2 / (1 - r^2), 10 at r ~ 0.95)
EXTRAPOLATION = 10.0

# what classify returns, per run
(
    C_KIND, C_START, C_END, C_PERIOD, C_NPER, C_DECAY, C_HEAD, C_LIMX, C_LIMA, C_JITTER,
) = range(10)
NC = 10


@njit(cache=True)
def tail_start(t0: float, t_end: float) -> float:
    """Start of the tail used for the equilibrium test."""
    span = t_end - t0
    return t_end - min(span, max(0.1 * span, 4.0 * math.pi))


@njit(cache=True)
def put(dst, src):
    """``dst[:] = src[:len(dst)]`` as a loop: numpy's slice assignment compiles its shape-error messages
    (string code, about 1.5 s) in every process that compiles a kernel using it."""
    for i in range(min(len(dst), len(src))):
        dst[i] = src[i]


@njit(cache=True)
def stats(a):
    """(min, max, sum, any NaN) of the 1-D array (or column view) ``a``; min and max are NaN if any value is.

    One loop for the reductions the classifier needs: numpy's reductions would
    each compile their own implementation on a fresh cache.  Callers pass views
    (``rec[i0:i1, COL]``), never a constant column number: numba would compile
    this once per constant.
    """
    lo = np.inf
    hi = -np.inf
    total = 0.0
    nan = False
    for v in a:
        if math.isnan(v):
            nan = True
        lo = v if v < lo else lo
        hi = v if v > hi else hi
        total += v
    if nan:
        return np.nan, np.nan, total, True
    return lo, hi, total, False


@njit(cache=True)
def records_from_samples(t, x, v, mode, dwork, zeta, t_tail):
    """Section records, tail and final aggregates of a sampled run.

    ``dwork[i]``: the work integrals over (t[i-1], t[i]].  A period's
    aggregates and work integrals cover the samples from the first sample
    after one crossing to the first sample after the next, both included,
    and the steps between them: the same span as the window they are
    averaged over.  The batched kernels build the same records while they
    integrate.
    """
    n = len(t)
    count = 0
    for i in range(n - 1):
        if v[i] > 0.0 and v[i + 1] <= 0.0:
            count += 1
    rec = np.empty((count, NF))
    tail = np.empty(NA)
    fin = np.empty(NA)
    rec[:] = np.nan  # (filling with a scalar compiles nothing; np.full would)
    tail[:] = np.nan
    fin[:] = np.nan
    agg = np.zeros(6)  # xmin, xmax, vmin, vmax, fmax, stick of the running period
    tag = np.zeros(6)  # the same over the tail (X extremes used only there)
    pw = np.zeros(4)  # work integrals of the running period
    tw = np.zeros(4)  # and of the tail
    k = -1
    lo = np.nan
    in_tail = False
    for i in range(n):
        xi, vi = x[i], v[i]
        fi = abs(xi + 2.0 * zeta * vi)
        if i > 0:
            h = t[i] - t[i - 1]
            stuck = h if mode[i - 1] == 0 else 0.0
            update(agg, xi, vi, fi, stuck)
            update(tag, xi, vi, fi, stuck)
            for j in range(4):
                pw[j] += dwork[i, j]
                if in_tail:
                    tw[j] += dwork[i, j]
            if v[i - 1] > 0.0 and vi <= 0.0:
                k += 1
                s = v[i - 1] / (v[i - 1] - vi)
                close(rec[k], t[i - 1] + s * h, hermite(x[i - 1], xi, v[i - 1] * h, vi * h, s), t[i], xi, vi, pw, agg, lo, k > 0)
                lo = np.nan
                reset(agg, xi, vi, fi)
                pw[:] = 0.0
            elif v[i - 1] < 0.0 and vi >= 0.0:
                s = v[i - 1] / (v[i - 1] - vi)
                lo = hermite(x[i - 1], xi, v[i - 1] * h, vi * h, s)
        if not in_tail and t[i] >= t_tail:
            in_tail = True
            mark(tail, t[i], xi, vi, tw)
            reset(tag, xi, vi, fi)
    store_tail(tail, tag, tw)
    total = np.zeros(4)
    for i in range(n):
        for j in range(4):
            total[j] += dwork[i, j]
    mark(fin, t[n - 1], x[n - 1], v[n - 1], total)
    fin[A_E0] = 0.5 * (x[0] * x[0] + v[0] * v[0])
    fin[A_XEND], fin[A_VEND] = x[n - 1], v[n - 1]
    return rec, tail, fin


@njit(cache=True, inline="always")
def update(agg, x, v, f, stuck):
    agg[0] = min(agg[0], x)
    agg[1] = max(agg[1], x)
    agg[2] = min(agg[2], v)
    agg[3] = max(agg[3], v)
    agg[4] = max(agg[4], f)
    agg[5] += stuck


@njit(cache=True, inline="always")
def reset(agg, x, v, f):
    agg[0] = x
    agg[1] = x
    agg[2] = v
    agg[3] = v
    agg[4] = f
    agg[5] = 0.0


@njit(cache=True, inline="always")
def close(r, tc, xc, ts, x, v, w, agg, lo, with_period):
    """Fill record ``r`` for a crossing at ``tc``; ``ts, x, v, w``: the sample after it."""
    r[T] = tc
    r[X] = xc
    r[TS] = ts
    r[ES] = 0.5 * (x * x + v * v)
    for j in range(4):
        r[W0 + j] = w[j]
    if with_period:
        r[VMIN] = agg[2]
        r[VMAX] = agg[3]
        r[FMAX] = agg[4]
        r[STICK] = agg[5]
        r[LO] = lo


@njit(cache=True, inline="always")
def mark(a, t, x, v, w):
    a[A_T] = t
    a[A_E] = 0.5 * (x * x + v * v)
    for j in range(4):
        a[A_W0 + j] = w[j]


@njit(cache=True, inline="always")
def store_tail(tail, tag, tw):
    for j in range(4):
        tail[A_W0 + j] = tw[j]
    tail[A_XMIN] = tag[0]
    tail[A_XMAX] = tag[1]
    tail[A_VMIN] = tag[2]
    tail[A_VMAX] = tag[3]
    tail[A_FMAX] = tag[4]
    tail[A_STICK] = tag[5]


@njit(cache=True)
def _repeat_count(seq, tol):
    m = 0
    n = len(seq)
    while m < n - 1 and abs(seq[n - 2 - m] - seq[n - 1]) <= tol:
        m += 1
    return m


@njit(cache=True)
def repeat_counts(xs, ts, tol_x, rtol, h2):
    """How far back the section values repeat the last ones: (maxima, periods).

    ``xs``, ``ts``: the maxima of X and their times, oldest first.  Counts the
    maxima before the last that equal it within ``tol_x``, and the periods
    (differences of ``ts``) before the last that equal it within ``rtol``
    times it plus ``h2``, consecutively back from the end.  The one test of
    periodicity, shared by :func:`classify` and the exact kernel's early stop.
    """
    n = len(xs)
    m_x = _repeat_count(xs, tol_x)
    m_p = 0
    if n >= 2:
        p_last = ts[n - 1] - ts[n - 2]
        tol_p = rtol * p_last + h2
        while m_p < n - 2 and abs((ts[n - 2 - m_p] - ts[n - 3 - m_p]) - p_last) <= tol_p:
            m_p += 1
    return m_x, m_p


@njit(cache=True)
def _monotone_amplitude(rec, i0, noise):
    """The amplitudes X - LO of the records from ``i0`` on shrink (or grow) at every step by more than ``noise``.

    A converged cycle whose window still holds the last step of its transient
    changes by rounding after it: not monotone.
    """
    n = rec.shape[0]
    if n - i0 < 3:
        return False
    first = rec[i0 + 1, X] - rec[i0 + 1, LO] - (rec[i0, X] - rec[i0, LO])
    sign = 1.0 if first > 0.0 else -1.0
    for i in range(i0 + 1, n):
        if not sign * ((rec[i, X] - rec[i, LO]) - (rec[i - 1, X] - rec[i - 1, LO])) > noise:
            return False
    return True


@njit(cache=True)
def push_section(ring_x, ring_t, x, t):
    """Shift the section value ``x`` at time ``t`` into a ring of the last ones, oldest first."""
    m = len(ring_x)
    for i in range(m - 1):
        ring_x[i] = ring_x[i + 1]
        ring_t[i] = ring_t[i + 1]
    ring_x[m - 1] = x
    ring_t[m - 1] = t


@njit(cache=True)
def ring_repeats(ring_x, ring_t, n, tol_x, rtol):
    """A full ring (``n`` values pushed) whose last ``len - 2`` values and periods repeat the newest (:func:`repeat_counts`)."""
    m = len(ring_x)
    if n < m:
        return False
    m_x, m_p = repeat_counts(ring_x, ring_t, tol_x, rtol, 0.0)
    return m_x >= m - 2 and m_p >= m - 2


@njit(cache=True)
def _stationary(seq):
    """No significant linear trend (|t| < 4) in a short noisy sequence."""
    n = len(seq)
    km = 0.5 * (n - 1)
    ym = 0.0
    for i in range(n):
        ym += seq[i]
    ym /= n
    sxx = 0.0
    sxy = 0.0
    for i in range(n):
        sxx += (i - km) ** 2
        sxy += (i - km) * (seq[i] - ym)
    slope = sxy / sxx
    ss = 0.0
    for i in range(n):
        r = seq[i] - ym - slope * (i - km)
        ss += r * r
    se = math.sqrt(ss / (n - 2) / sxx)
    if se == 0.0:
        return slope == 0.0
    return abs(slope) / se < 4.0


@njit(cache=True)
def _aitken(a0, a1, a2):
    den = a2 - 2.0 * a1 + a0
    if den == 0.0:
        return a2
    return a2 - (a2 - a1) ** 2 / den


@njit(cache=True)
def state_repeats(zs, tol):
    """How far back every column of ``zs`` (section values of further states, oldest first) repeats its
    last value within ``tol``: the fewest over the columns (``len(zs) - 1`` when there are none)."""
    m = zs.shape[0] - 1
    for c in range(zs.shape[1]):
        m = min(m, _repeat_count(zs[:, c].copy(), tol))
    return m


@njit(cache=True, forceinline=True)
def _periodic_strictly(out, rec, zs, tol, rtol, min_periods, h, noise):
    """Maxima, minima, periods and the further states ``zs`` repeat to tol (:func:`classify_state`): fill
    ``out`` and return True, else False."""
    n = rec.shape[0]
    if n < min_periods + 1:
        return False
    lo_min, lo_max, _, lo_nan = stats(rec[n - min_periods : n, LO])
    amp = rec[n - 1, X] - rec[n - 1, LO]
    tol_c = max(rtol * amp, noise) if amp > 0.0 else tol
    m_x, m_p = repeat_counts(rec[:, X].copy(), rec[:, T].copy(), tol_c, rtol, h * h)
    m = min(m_x, m_p + 1, state_repeats(zs, tol_c))
    if (m >= min_periods and not lo_nan and lo_max - lo_min <= tol_c
            and not _monotone_amplitude(rec, n - 1 - min_periods, 2.0 * noise)):
        out[C_KIND] = PERIODIC
        out[C_START] = n - 1 - m
        out[C_END] = n - 1
        out[C_PERIOD] = (rec[n - 1, T] - rec[n - 1 - m, T]) / m
        out[C_NPER] = m
        return True
    return False


@njit(cache=True, forceinline=True)
def _periodic_jitter(out, rec, min_periods):
    """Periodic to within the jitter of a fixed step through a stick band (:func:`classify`): fill ``out`` and return True, else False."""
    n = rec.shape[0]
    k = min(n - 1, 12)
    if k < max(min_periods, 8):
        return False
    lo_min, lo_max, _, lo_nan = stats(rec[n - k : n, LO])
    if not (stats(rec[n - k : n, STICK])[1] > 0.0 and not lo_nan):
        return False
    xs = rec[n - 1 - k : n, X].copy()
    lo = rec[n - k : n, LO].copy()
    periods = np.empty(k)
    p_min, p_max = np.inf, -np.inf
    for i in range(k):
        periods[i] = rec[n - k + i, T] - rec[n - 1 - k + i, T]
        p_min, p_max = min(p_min, periods[i]), max(p_max, periods[i])
    x_min, x_max, _, _ = stats(rec[n - 1 - k : n, X])
    amp = x_max - lo_min
    jitter = max(x_max - x_min, lo_max - lo_min) / amp if amp > 0 else 0.0
    if (
        jitter < 0.05
        and p_max - p_min < 0.05 * periods[-1]
        and _stationary(xs)
        and _stationary(lo)
        and _stationary(periods)
    ):
        out[C_KIND] = PERIODIC
        out[C_START] = n - 1 - k
        out[C_END] = n - 1
        out[C_PERIOD] = (rec[n - 1, T] - rec[n - 1 - k, T]) / k
        out[C_NPER] = k
        out[C_JITTER] = jitter
        return True
    return False


@njit(cache=True, forceinline=True)
def _amplitude_slope(rec, use):
    """(ok, slope): the least-squares slope of log((X - LO) / 2) against T over the last ``use`` records; not ok if an amplitude is not positive."""
    n = rec.shape[0]
    tm = 0.0
    lm = 0.0
    for i in range(n - use, n):
        a = 0.5 * (rec[i, X] - rec[i, LO])
        if a <= 0.0:
            return False, 0.0
        tm += rec[i, T]
        lm += math.log(a)
    tm /= use
    lm /= use
    sxy = 0.0
    sxx = 0.0
    for i in range(n - use, n):
        dt = rec[i, T] - tm
        sxy += dt * (math.log(0.5 * (rec[i, X] - rec[i, LO])) - lm)
        sxx += dt * dt
    return True, sxy / sxx


@njit(cache=True, forceinline=True)
def _heading(out, rec, tol, slope):
    """Where a run that is not settled is heading (``C_HEAD``), with the limit centre and amplitude (Aitken) of the last three records."""
    n = rec.shape[0]
    amp = np.empty(3)
    cen = np.empty(3)
    for i in range(3):
        amp[i] = 0.5 * (rec[n - 3 + i, X] - rec[n - 3 + i, LO])
        cen[i] = 0.5 * (rec[n - 3 + i, X] + rec[n - 3 + i, LO])
    a_inf = _aitken(amp[0], amp[1], amp[2])
    c_inf = _aitken(cen[0], cen[1], cen[2])
    if -slope > 0.0:
        if a_inf <= max(tol, 1e-3 * amp[2]):
            out[C_HEAD] = HEAD_EQUILIBRIUM
            out[C_LIMX] = c_inf
        elif amp[2] - a_inf <= EXTRAPOLATION * abs(amp[0] - amp[2]):
            out[C_HEAD] = HEAD_PERIODIC
            out[C_LIMX] = c_inf
            out[C_LIMA] = a_inf
        # else a limit far beyond the records' own change (a slow decay, amplitude ratio above ~0.95 a period):
        # unresolved -- the second differences are then the rounding of the extrema or a weak nonlinearity
        # (a supercritical Hopf point's cubic damping reads as a limit cycle of a few % of the amplitude)
    else:
        out[C_HEAD] = HEAD_GROWING


@njit(cache=True, forceinline=True)
def _not_settled(out, rec, tol):
    """Fill ``out`` for a run that is not settled: the last period as its window, and where it is going."""
    n = rec.shape[0]
    out[C_KIND] = NOT_SETTLED
    if n >= 2:
        out[C_START] = n - 2
        out[C_END] = n - 1
    else:
        out[C_START] = -1
        out[C_END] = -1
    # amplitudes of the periods that have a minimum
    j0 = n
    while j0 > 0 and not math.isnan(rec[j0 - 1, LO]):
        j0 -= 1
    kk = n - j0
    if kk >= 2:
        ok, slope = _amplitude_slope(rec, min(kk, 3))  # the latest behaviour, not the early transient
        if ok:
            out[C_DECAY] = -slope
            if kk >= 3:
                _heading(out, rec, tol, slope)


@njit(cache=True)
def classify(rec, tail, scale, rtol, min_periods, h, fixed_step, noise):
    """Periodic / equilibrium / not settled from section records (:func:`classify_state` with no further states)."""
    return classify_state(rec, np.empty((rec.shape[0], 0)), 0.0, tail, scale, rtol, min_periods, h, fixed_step, noise)


@njit(cache=True)
def classify_state(rec, zs, z_spread, tail, scale, rtol, min_periods, h, fixed_step, noise):
    """Periodic / equilibrium / not settled from section records and the state beyond (X, X').

    ``rec`` holds the run's records in time order; ``zs`` (one row per
    record) the further states at each crossing (a law's internal states,
    in the units of X: scaled so that 1 carries the force 1), and
    ``z_spread`` their largest range over the tail.  A periodic orbit
    repeats in the whole state on the section, an equilibrium holds it all
    still.  Repetition is judged
    relative to the oscillation's own amplitude (``rtol`` times it), never
    finer than ``noise``, the solver's error in a section value; an
    oscillation whose amplitude shrinks or grows monotonically by more than
    that noise is never periodic.  Returns an array
    (layout ``C_*``): the kind, the first and last record of the window
    (-1: the tail), the period, the number of periods, and for runs that are
    not settled the amplitude's decay rate, where it is heading
    (``HEAD_*``), the limit centre or amplitude (Aitken) -- and the jitter
    of noisy fixed-step orbits.
    """
    out = np.empty(NC)
    out[:] = np.nan
    out[C_NPER] = 0.0
    out[C_HEAD] = HEAD_NONE
    tol = rtol * scale
    # Equilibrium: nothing moves over the tail -- X, X' and the further states stay put, and X' stays at 0 (a
    # tail too short for X to move, of a mass carried at V_b, is not one)
    if (tail[A_XMAX] - tail[A_XMIN] <= tol and tail[A_VMAX] - tail[A_VMIN] <= tol
            and max(abs(tail[A_VMAX]), abs(tail[A_VMIN])) <= tol and z_spread <= tol):
        out[C_KIND] = EQUILIBRIUM
        out[C_START] = -1
        out[C_END] = -1
        out[C_LIMX] = 0.5 * (tail[A_XMAX] + tail[A_XMIN])
        return out
    if _periodic_strictly(out, rec, zs, tol, rtol, min_periods, h, noise):
        return out
    if fixed_step and _periodic_jitter(out, rec, min_periods):
        return out
    _not_settled(out, rec, tol)  # measure where it is going
    return out


@njit(cache=True)
def scale_of(rec, tail, vb, fd):
    """The motion's scale: max(range of X, range of X', |V_b|, F_d) over the records and the tail."""
    xmin, xmax = tail[A_XMIN], tail[A_XMAX]
    vmin, vmax = tail[A_VMIN], tail[A_VMAX]
    for i in range(rec.shape[0]):
        xmax = max(xmax, rec[i, X])
        if not math.isnan(rec[i, LO]):
            xmin = min(xmin, rec[i, LO])
            vmin = min(vmin, rec[i, VMIN])
            vmax = max(vmax, rec[i, VMAX])
    return max(xmax - xmin, vmax - vmin, abs(vb), fd, 1e-300)


# Positions of the quantities in the table's layout (frictionflow.quantities):
# averages, window_summary and equilibrium_row fill rows of it.  Numba reads
# these module globals as compile-time constants.
KIND, PERIOD, P_DV, P_DF, P_FIN, P_F, P_BELT, P_HEAT, P_EX, R_C, R_F, RESID = (
    Q.index(n) for n in ("kind", "period", "P_dv", "P_df", "P_fin", "P_f", "P_belt", "P_heat", "P_ex", "R_c", "R_f",
                         "energy_residual")
)
S_TRB, S_XMIN, S_XMAX, S_VMIN, S_VMAX, S_STICK = (
    Q.index(n) for n in ("TR_B", "X_min", "X_max", "V_min", "V_max", "stick_fraction")
)
NQ = Q.NQ
# window_summary also returns the window, after the quantities
S_T0, S_T1 = NQ, NQ + 1
NS = NQ + 2
# the value of each quantity at an equilibrium: its rule's position in Q.EQUILIBRIUM_RULES
EQ_RULE = tuple(Q.EQUILIBRIUM_RULES.index(q.at_equilibrium) for q in Q.TABLE)


#: the friction input below which R_c and R_f are undefined, relative to the window's largest flow
RATIO_FLOOR = 1e-12


@njit(cache=True)
def averages(dw_dv, dw_in, dw_out, dw_heat, dw_ex, e0, e1, span):
    """Window averages from the work integrals over the window and the change of K + U.

    The balance is Delta(K + U) = W_fin - W_fout + W_ex - W_dv (``dw_ex``: the
    external force's work, 0 unforced).  Its residual is relative to the
    largest flow (the friction input, unforced; for a whole number of
    periods they are the same), but never to less than 1e-12 of the stored
    energy K + U: below that the
    change of K + U itself is lost to rounding, so the balance cannot be
    checked more finely (deep in a decay, or at an equilibrium).  The ratios
    R_c, R_f are NaN when friction puts in nothing above rounding: W_fin at
    most :data:`RATIO_FLOOR` times the largest flow of the window.  Returns a row of the table's
    layout with the averages and the residual filled in (the rest NaN).
    """
    out = np.empty(NQ)
    out[:] = np.nan
    w_f = dw_in - dw_out
    floor = 1e-12 * max(e0, e1)
    resid = abs(e1 - e0 + dw_dv - w_f - dw_ex)
    norm = max(dw_in, dw_out, dw_dv, abs(dw_ex), floor)
    out[P_DV] = dw_dv / span
    out[P_DF] = dw_out / span
    out[P_FIN] = dw_in / span
    out[P_F] = w_f / span
    out[P_BELT] = (w_f + dw_heat) / span
    out[P_HEAT] = dw_heat / span
    out[P_EX] = dw_ex / span
    # The ratios divide by the friction input; below 1e-12 of the largest flow it is rounding of the
    # pieces summed into it (each cancels terms of that flow's size: a belt at rest puts in nothing).
    ratios = dw_in > RATIO_FLOOR * norm
    out[R_C] = dw_dv / dw_in if ratios else np.nan
    out[R_F] = dw_out / dw_in if ratios else np.nan
    out[RESID] = resid / norm if norm > 0 else 0.0
    return out


@njit(cache=True)
def equilibrium_row(x, vb, fd, stick, resid):
    """Every quantity's value at the equilibrium X* = ``x`` (a row of the table's layout).

    Each quantity's rule (its ``at_equilibrium`` in :mod:`frictionflow.quantities`)
    picks its value: no motion, no friction input, the belt's power X* V_b
    all heat while the mass rests sliding (0 resting in a stick band,
    ``stick`` >= 1/2), TR_B = |X*| / F_d; ``stick`` and ``resid`` are the
    stick fraction and energy residual to report.
    """
    belt = 0.0 if stick >= 0.5 else x * vb
    trb = abs(x) / fd if fd > 0.0 else np.nan
    # one value per rule, in the order of Q.EQUILIBRIUM_RULES
    value = np.empty(8)
    value[0], value[1], value[2], value[3] = float(EQUILIBRIUM), np.nan, 0.0, x
    value[4], value[5], value[6], value[7] = belt, trb, stick, resid
    out = np.empty(NQ)
    for i in range(NQ):
        out[i] = value[EQ_RULE[i]]
    return out


@njit(cache=True)
def window_summary(rec, tail, fin, cls, fd, vb):
    """Every quantity over the classified window (table layout), then the window (``S_T0``, ``S_T1``).

    For an equilibrium they are the equilibrium's own (:func:`equilibrium_row`);
    the residual is the whole run's.
    """
    out = np.empty(NS)
    out[:] = np.nan
    i0 = int(cls[C_START])
    i1 = int(cls[C_END])
    if i0 < 0:  # the tail
        a, b = tail, fin
        span = b[A_T] - a[A_T]
        xmin, xmax, vmin, vmax = tail[A_XMIN], tail[A_XMAX], tail[A_VMIN], tail[A_VMAX]
        fmax, stick = tail[A_FMAX], tail[A_STICK]
        dw = np.empty(4)
        for j in range(4):
            dw[j] = tail[A_W0 + j]
        e0, e1 = a[A_E], b[A_E]
        t0, t1 = a[A_T], b[A_T]
    else:  # the periods that end at records i0 + 1 .. i1
        t0, t1 = rec[i0, TS], rec[i1, TS]
        span = t1 - t0
        xmin = stats(rec[i0 + 1 : i1 + 1, LO])[0]
        xmax = stats(rec[i0 : i1 + 1, X])[1]
        vmin = stats(rec[i0 + 1 : i1 + 1, VMIN])[0]
        vmax = stats(rec[i0 + 1 : i1 + 1, VMAX])[1]
        fmax = stats(rec[i0 + 1 : i1 + 1, FMAX])[1]
        stick = stats(rec[i0 + 1 : i1 + 1, STICK])[2]
        dw = np.empty(4)
        for j in range(4):
            dw[j] = stats(rec[i0 + 1 : i1 + 1, W0 + j])[2]
        e0, e1 = rec[i0, ES], rec[i1, ES]
    if span > 0:
        put(out, averages(dw[0], dw[1], dw[2], dw[3], 0.0, e0, e1, span))
        out[S_STICK] = stick / span
    out[KIND] = cls[C_KIND]
    if cls[C_KIND] == PERIODIC:
        out[PERIOD] = cls[C_PERIOD]
    out[S_T0] = t0
    out[S_T1] = t1
    out[S_TRB] = fmax / fd if fd > 0 else np.nan
    out[S_XMIN] = xmin
    out[S_XMAX] = xmax
    out[S_VMIN] = vmin
    out[S_VMAX] = vmax
    if cls[C_KIND] == EQUILIBRIUM:
        # the balance of the whole run (at rest there is nothing left to check)
        whole = averages(fin[A_W0], fin[A_W1], fin[A_W2], fin[A_W3], 0.0, fin[A_E0], fin[A_E], max(fin[A_T], 1e-300))
        put(out, equilibrium_row(cls[C_LIMX], vb, fd, out[S_STICK], whole[RESID]))
    return out
