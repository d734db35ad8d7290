"""RK4 for many parameter points at once, keeping section records instead of samples.

Lanes (parameter points) are integrated in blocks of ``LANES`` in lock step:
the inner loop over a block's lanes is free of branches the compiler cannot
turn into selects, so it vectorises (SIMD), and blocks run in parallel over
the cores.  Crossings of the section X' = 0 are rare; a vectorised test
finds the steps with one, and a scalar pass over the block handles them.  What each lane keeps is its last
``K`` section records, its tail aggregates and its final sample
(:mod:`frictionflow.core.sections`), enough to classify its steady state and
average over it without storing a trajectory.

The block's per-lane arrays travel in records (tuples, built once per block;
numba inlines the callees that take them, see the README's compile-time
rules): ``lane`` = (zeta, V_b, F_d, F_s, V_d, resultant, a, b, c), the
lanes' parameters; ``st`` = (X, X', X and X' before the step); ``w``, the
running period's four work integrals; ``per`` = (min X', max X', max |F_e|,
stick time, the low section) of the running period; ``tl`` = (min and max
of X, of X', max |F_e|, stick time) of the tail; ``sums`` = (the tail's
work, the whole run's work), (L, 4) each; ``out`` = (rec, nrec, tail, fin).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from . import sections as sec
from ._vectorize import wide_vectors
from .friction import BAND_LAWS, COULOMB, CUBIC, FD, FS, KARNOPP, LAW_A, LAW_B, LAW_C, N_PARAMS, RESULTANT, STRIBECK, VD
from .rk4 import FASTMATH, constant_drive, step
from .threads import over_points

LANES = 64


@njit(cache=True, fastmath=FASTMATH, forceinline=True)
def _lanes(law, switch, st, w, dt, lane):
    """One RK4 step of every lane (vectorised); ``switch``: the law has Coulomb's stick rule (see
    :func:`~.friction.band_law`)."""
    x, v, xo, vo = st
    w0, w1, w2, w3 = w
    zeta, vb, fd, fs, vd, res, la, lb, lc = lane
    for j in range(len(x)):
        xj = x[j]
        vj = v[j]
        lw = (law, fd[j], fs[j], vd[j], res[j], la[j], lb[j], lc[j], switch)
        xn, vn, d0, d1, d2, d3, _ = step(xj, vj, dt, zeta[j], lw, True, constant_drive(vb[j]), False)
        w0[j] += d0
        w1[j] += d1
        w2[j] += d2
        w3[j] += d3
        xo[j] = xj
        vo[j] = vj
        x[j] = xn
        v[j] = vn


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _aggregates(dt, in_tail, st, lane, per, tl):
    """The running period's aggregates after a step, and the tail's once in it (vectorised).

    Returns whether X' crossed 0 in any lane: the crossing pass runs only
    then, as it unpacks many records around a loop that makes views, and
    numba cannot drop the reference counts of those (atomic operations):
    every step they would cost more than the step.
    """
    x, v, _, vo = st
    zeta, vb, vd = lane[0], lane[1], lane[4]
    pvmin, pvmax, pfmax, pstk, _ = per
    crossed = False
    for j in range(len(x)):
        vn = v[j]
        crossed |= ((vo[j] > 0.0) & (vn <= 0.0)) | ((vo[j] < 0.0) & (vn >= 0.0))
        f = abs(x[j] + 2.0 * zeta[j] * vn)
        pvmin[j] = vn if vn < pvmin[j] else pvmin[j]
        pvmax[j] = vn if vn > pvmax[j] else pvmax[j]
        pfmax[j] = f if f > pfmax[j] else pfmax[j]
        pstk[j] += dt if abs(vb[j] - vo[j]) <= vd[j] else 0.0
    if in_tail:
        txmin, txmax, tvmin, tvmax, tfmax, tstk = tl
        for j in range(len(x)):
            xn = x[j]
            vn = v[j]
            f = abs(xn + 2.0 * zeta[j] * vn)
            txmin[j] = xn if xn < txmin[j] else txmin[j]
            txmax[j] = xn if xn > txmax[j] else txmax[j]
            tvmin[j] = vn if vn < tvmin[j] else tvmin[j]
            tvmax[j] = vn if vn > tvmax[j] else tvmax[j]
            tfmax[j] = f if f > tfmax[j] else tfmax[j]
            tstk[j] += dt if abs(vb[j] - vo[j]) <= vd[j] else 0.0
    return crossed


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _crossings(i, dt, in_tail, st, w, lane, per, sums, scratch, out):
    """Scalar and rare: close a period at each downward crossing of X' = 0 in step ``i``, note the upward ones."""
    x, v, xo, vo = st
    w0, w1, w2, w3 = w
    zeta = lane[0]
    pvmin, pvmax, pfmax, pstk, lo = per
    tws, tot = sums
    agg, wj = scratch
    rec, nrec = out[0], out[1]
    K = rec.shape[1]
    ti = (i + 1) * dt
    for j in range(len(x)):
        a = vo[j]
        b = v[j]
        if a > 0.0 and b <= 0.0:
            s = a / (a - b)
            agg[2], agg[3], agg[4], agg[5] = pvmin[j], pvmax[j], pfmax[j], pstk[j]
            wj[0], wj[1], wj[2], wj[3] = w0[j], w1[j], w2[j], w3[j]
            slot = nrec[j] % K
            rec[j, slot, :] = np.nan
            xc = sec.hermite(xo[j], x[j], a * dt, b * dt, s)
            sec.close(rec[j, slot], i * dt + s * dt, xc, ti, x[j], b, wj, agg, lo[j], nrec[j] > 0)
            nrec[j] += 1
            for q in range(4):
                tot[j, q] += wj[q]
                if in_tail:
                    tws[j, q] += wj[q]
            w0[j] = w1[j] = w2[j] = w3[j] = 0.0
            lo[j] = np.nan
            pvmin[j] = pvmax[j] = b
            pfmax[j] = abs(x[j] + 2.0 * zeta[j] * b)
            pstk[j] = 0.0
        elif a < 0.0 and b >= 0.0:
            s = a / (a - b)
            lo[j] = sec.hermite(xo[j], x[j], a * dt, b * dt, s)
@njit(cache=True, fastmath=FASTMATH, inline="always")
def _start_tail(t, st, w, lane, tl, tws, wj, tail):
    """The tail begins at ``t``: its work starts from minus the running period's, its aggregates from the state."""
    x, v = st[0], st[1]
    zeta = lane[0]
    txmin, txmax, tvmin, tvmax, tfmax, tstk = tl
    for j in range(len(x)):
        tws[j, 0], tws[j, 1], tws[j, 2], tws[j, 3] = -w[0][j], -w[1][j], -w[2][j], -w[3][j]
        sec.mark(tail[j], t, x[j], v[j], wj)
        txmin[j] = txmax[j] = x[j]
        tvmin[j] = tvmax[j] = v[j]
        tfmax[j] = abs(x[j] + 2.0 * zeta[j] * v[j])
        tstk[j] = 0.0


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _finish(t, x0, v0, st, w, tl, sums, wj, out):
    """The tail's work and aggregates into ``tail``, the final sample and the whole run's work into ``fin``."""
    x, v = st[0], st[1]
    w0, w1, w2, w3 = w
    txmin, txmax, tvmin, tvmax, tfmax, tstk = tl
    tws, tot = sums
    tail, fin = out[2], out[3]
    for j in range(len(x)):
        tail[j, sec.A_W0], tail[j, sec.A_W1] = tws[j, 0] + w0[j], tws[j, 1] + w1[j]
        tail[j, sec.A_W2], tail[j, sec.A_W3] = tws[j, 2] + w2[j], tws[j, 3] + w3[j]
        tail[j, sec.A_XMIN], tail[j, sec.A_XMAX] = txmin[j], txmax[j]
        tail[j, sec.A_VMIN], tail[j, sec.A_VMAX] = tvmin[j], tvmax[j]
        tail[j, sec.A_FMAX], tail[j, sec.A_STICK] = tfmax[j], tstk[j]
        wj[0], wj[1], wj[2], wj[3] = tot[j, 0] + w0[j], tot[j, 1] + w1[j], tot[j, 2] + w2[j], tot[j, 3] + w3[j]
        sec.mark(fin[j], t, x[j], v[j], wj)
        fin[j, sec.A_E0] = 0.5 * (x0[j] * x0[j] + v0[j] * v0[j])
        fin[j, sec.A_XEND], fin[j, sec.A_VEND] = x[j], v[j]


@njit(cache=True, fastmath=FASTMATH)
def _block(law, pts, run, out):
    """The lanes ``pts`` = (zeta, V_b, p, X0, X'0) of one block for ``run`` = (dt, n_steps, t_tail), into ``out``."""
    zeta, vb, p, x0, v0 = pts
    dt, n_steps, t_tail = run
    # Every per-lane quantity is its own 1-D array allocated here: the
    # compiler then knows they do not overlap and vectorises the lane loops.
    L = len(zeta)
    lane = (zeta.copy(), vb.copy(), p[:, FD].copy(), p[:, FS].copy(), p[:, VD].copy(), p[:, RESULTANT] != 0.0,
            p[:, LAW_A].copy(), p[:, LAW_B].copy(), p[:, LAW_C].copy())
    zeta = lane[0]
    switch = law not in BAND_LAWS
    st = (x0.copy(), v0.copy(), x0.copy(), v0.copy())
    x, v = st[0], st[1]
    w = (np.zeros(L), np.zeros(L), np.zeros(L), np.zeros(L))  # work of the running period
    # The tail's work: periods closed in the tail, minus what the period under
    # way when the tail began had done by then, plus the open period at the end;
    # and the whole run's work (closed periods).
    sums = (np.zeros((L, 4)), np.zeros((L, 4)))
    f0 = np.abs(x + 2.0 * zeta * v)
    # aggregates of the running period, and of the tail
    per = (v.copy(), v.copy(), f0.copy(), np.zeros(L), np.full(L, np.nan))
    tl = (x.copy(), x.copy(), v.copy(), v.copy(), f0.copy(), np.zeros(L))
    scratch = (np.zeros(6), np.zeros(4))
    wj = scratch[1]
    in_tail = t_tail <= 0.0
    if in_tail:
        for j in range(L):
            sec.mark(out[2][j], 0.0, x[j], v[j], wj)
    for i in range(n_steps):
        # Each law's loop is compiled with its code as a constant, so that it holds
        # only that law's slip force: another law's branch (a call to exp, say)
        # would keep every loop from vectorising.  (``+ 0`` and the branches: see
        # rk4.run; _lanes is inlined by LLVM, so numba types it once.)
        if law == KARNOPP or law == COULOMB:
            _lanes(KARNOPP + 0, switch, st, w, dt, lane)
        elif law == STRIBECK:
            _lanes(STRIBECK + 0, switch, st, w, dt, lane)
        elif law == CUBIC:
            _lanes(CUBIC + 0, switch, st, w, dt, lane)
        if _aggregates(dt, in_tail, st, lane, per, tl):
            _crossings(i, dt, in_tail, st, w, lane, per, sums, scratch, out)
        ti = (i + 1) * dt
        if not in_tail and ti >= t_tail:
            in_tail = True
            _start_tail(ti, st, w, lane, tl, sums[0], wj, out[2])
    _finish(n_steps * dt, x0, v0, st, w, tl, sums, wj, out)


def run_batch(law, zeta, vb, p, x0, v0, dt, n_steps, t_tail) -> tuple[np.ndarray, ...]:
    """Integrate every lane for ``n_steps``; returns (rec (B, K, NF), nrec, tail, fin), K = MAX_RECORDS. Blocks run in parallel."""
    n = len(zeta)
    out = (np.full((n, sec.MAX_RECORDS, sec.NF), np.nan), np.zeros(n, np.int64), np.full((n, sec.NA), np.nan),
           np.full((n, sec.NA), np.nan))
    over_points(_blocks, (n + LANES - 1) // LANES, law, (zeta, vb, p, x0, v0), (dt, n_steps, t_tail), out)
    return out


@njit(cache=True, nogil=True)
def _blocks(b0, b1, law, pts, run, out):
    """Blocks ``b0 .. b1-1`` of ``LANES`` lanes each: ``pts`` = (zeta, V_b, p, X0, X'0), ``out`` = (rec, nrec, tail, fin)."""
    zeta, vb, p, x0, v0 = pts
    rec, nrec, tail, fin = out
    n = len(zeta)
    for b in range(b0, b1):
        s = b * LANES
        e = min(n, s + LANES)
        _block(law, (zeta[s:e], vb[s:e], p[s:e], x0[s:e], v0[s:e]), run, (rec[s:e], nrec[s:e], tail[s:e], fin[s:e]))


_warm = False


def warm_up() -> None:
    """Compile (or load from the cache) the batched kernels with wide vectors, once per process."""
    global _warm
    if _warm:
        return

    z = np.zeros(1)
    p = np.zeros((1, N_PARAMS))
    out = (np.full((1, 2, sec.NF), np.nan), np.zeros(1, np.int64), np.full((1, sec.NA), np.nan), np.full((1, sec.NA), np.nan))
    with wide_vectors():
        _blocks(0, 1, 0, (z, z, p, z, z), (1e-3, 1, 0.0), out)
    _warm = True


@njit(cache=True)
def unroll(ring, count):
    """The records of one lane's ring in time order."""
    K = ring.shape[0]
    m = min(count, K)
    out = np.empty((m, ring.shape[1]))
    first = count - m
    for i in range(m):
        for q in range(ring.shape[1]):
            out[i, q] = ring[(first + i) % K, q]
    return out


def summarize(rec, nrec, tail, fin, vb, fd, rtol, min_periods, h, fixed_step, noise) -> np.ndarray:
    """Classify every lane and average over its window: (B, NC + NS), parallel over the cores."""
    out = np.empty((len(nrec), sec.NC + sec.NS))
    over_points(_summarize, len(nrec), (rec, nrec, tail, fin), vb, fd, (rtol, min_periods, h, fixed_step, noise), out)
    return out


@njit(cache=True, nogil=True)
def _summarize(j0, j1, runs, vb, fd, opts, out):
    """Lanes ``j0 .. j1-1``: ``runs`` = (rec, nrec, tail, fin) of :func:`run_batch`, ``opts`` = (rtol, min_periods, h, fixed_step, noise)."""
    rec, nrec, tail, fin = runs
    rtol, min_periods, h, fixed_step, noise = opts
    for j in range(j0, j1):
        r = unroll(rec[j], nrec[j])
        scale = sec.scale_of(r, tail[j], vb[j], fd[j])
        c = sec.classify(r, tail[j], scale, rtol, min_periods, h, fixed_step, noise * scale)
        s = sec.window_summary(r, tail[j], fin[j], c, fd[j], vb[j])
        for q in range(sec.NC):
            out[j, q] = c[q]
        for q in range(sec.NS):
            out[j, sec.NC + q] = s[q]
