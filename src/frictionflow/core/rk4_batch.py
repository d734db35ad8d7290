"""RK4 for many parameter points at once, keeping section records instead of samples.

Lanes (parameter points) are integrated in blocks of ``LANES`` in lock step:
the inner loop over a block's lanes is free of branches the compiler cannot
turn into selects, so it vectorises (SIMD), and blocks run in parallel over
the cores.  Crossings of the section X' = 0 are rare; they are handled by a
scalar pass over the block after each step.  What each lane keeps is its last
``K`` section records, its tail aggregates and its final sample
(:mod:`frictionflow.core.sections`), enough to classify its steady state and
average over it without storing a trajectory.
"""

from __future__ import annotations

import numpy as np
from numba import literal_unroll, njit

from . import sections as sec
from ._vectorize import wide_vectors
from .friction import COULOMB, FD, FS, KARNOPP, LAW_A, LAW_B, LAW_C, N_PARAMS, RESULTANT, SMOOTH_LAWS, VD
from .rk4 import FASTMATH, step
from .threads import over_points

LANES = 64


@njit(cache=True, fastmath=FASTMATH, inline="always")
def _lanes(law, x, v, xo, vo, w0, w1, w2, w3, dt, zeta, vb, fd, fs, vd, res, la, lb, lc):
    """One RK4 step of every lane (vectorised)."""
    for j in range(len(x)):
        xj = x[j]
        vj = v[j]
        xn, vn, d0, d1, d2, d3, _ = step(xj, vj, dt, zeta[j], vb[j], law, fd[j], fs[j], vd[j], res[j], la[j], lb[j], lc[j], True)
        w0[j] += d0
        w1[j] += d1
        w2[j] += d2
        w3[j] += d3
        xo[j] = xj
        vo[j] = vj
        x[j] = xn
        v[j] = vn


@njit(cache=True, fastmath=FASTMATH)
def _block(law, zeta, vb, p, x0, v0, dt, n_steps, t_tail, rec, nrec, tail, fin):
    # Every per-lane quantity is its own 1-D array allocated here: the
    # compiler then knows they do not overlap and vectorises the lane loops.
    L = len(zeta)
    K = rec.shape[1]
    zeta = zeta.copy()
    vb = vb.copy()
    fd = p[:, FD].copy()
    fs = p[:, FS].copy()
    vd = p[:, VD].copy()
    res = p[:, RESULTANT] != 0.0
    la = p[:, LAW_A].copy()
    lb = p[:, LAW_B].copy()
    lc = p[:, LAW_C].copy()
    x = x0.copy()
    v = v0.copy()
    xo = x0.copy()
    vo = v0.copy()
    w0, w1, w2, w3 = np.zeros(L), np.zeros(L), np.zeros(L), np.zeros(L)  # work of the running period
    # The tail's work: periods closed in the tail, minus what the period under
    # way when the tail began had done by then, plus the open period at the end.
    tws = np.zeros((L, 4))
    tot = np.zeros((L, 4))  # the whole run's work (closed periods)
    f0 = np.abs(x + 2.0 * zeta * v)
    # aggregates of the running period, and of the tail
    pvmin, pvmax, pfmax, pstk = v.copy(), v.copy(), f0.copy(), np.zeros(L)
    txmin, txmax, tvmin, tvmax, tfmax, tstk = x.copy(), x.copy(), v.copy(), v.copy(), f0.copy(), np.zeros(L)
    lo = np.full(L, np.nan)
    agg = np.zeros(6)
    wj = np.zeros(4)
    in_tail = t_tail <= 0.0
    if in_tail:
        for j in range(L):
            sec.mark(tail[j], 0.0, x[j], v[j], wj)
    for i in range(n_steps):
        # Each law's loop is compiled with its code as a constant, so that it holds
        # only that law's slip force: another law's branch (a call to exp, say)
        # would keep every loop from vectorising.  (``+ 0``: see rk4.run.)
        if law == KARNOPP or law == COULOMB:
            _lanes(KARNOPP + 0, x, v, xo, vo, w0, w1, w2, w3, dt, zeta, vb, fd, fs, vd, res, la, lb, lc)
        else:
            for code in literal_unroll(SMOOTH_LAWS):
                if law == code:
                    _lanes(code + 0, x, v, xo, vo, w0, w1, w2, w3, dt, zeta, vb, fd, fs, vd, res, la, lb, lc)
        for j in range(L):  # vectorised: the period's aggregates
            vn = v[j]
            f = abs(x[j] + 2.0 * zeta[j] * vn)
            pvmin[j] = vn if vn < pvmin[j] else pvmin[j]
            pvmax[j] = vn if vn > pvmax[j] else pvmax[j]
            pfmax[j] = f if f > pfmax[j] else pfmax[j]
            pstk[j] += dt if abs(vb[j] - vo[j]) <= vd[j] else 0.0
        if in_tail:
            for j in range(L):  # vectorised: the tail's aggregates
                xn = x[j]
                vn = v[j]
                f = abs(xn + 2.0 * zeta[j] * vn)
                txmin[j] = xn if xn < txmin[j] else txmin[j]
                txmax[j] = xn if xn > txmax[j] else txmax[j]
                tvmin[j] = vn if vn < tvmin[j] else tvmin[j]
                tvmax[j] = vn if vn > tvmax[j] else tvmax[j]
                tfmax[j] = f if f > tfmax[j] else tfmax[j]
                tstk[j] += dt if abs(vb[j] - vo[j]) <= vd[j] else 0.0
        ti = (i + 1) * dt
        for j in range(L):  # scalar and rare: section crossings
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
        if not in_tail and ti >= t_tail:
            in_tail = True
            for j in range(L):
                tws[j, 0], tws[j, 1], tws[j, 2], tws[j, 3] = -w0[j], -w1[j], -w2[j], -w3[j]
                sec.mark(tail[j], ti, x[j], v[j], wj)
                txmin[j] = txmax[j] = x[j]
                tvmin[j] = tvmax[j] = v[j]
                tfmax[j] = abs(x[j] + 2.0 * zeta[j] * v[j])
                tstk[j] = 0.0
    for j in range(L):
        tail[j, sec.A_W0], tail[j, sec.A_W1] = tws[j, 0] + w0[j], tws[j, 1] + w1[j]
        tail[j, sec.A_W2], tail[j, sec.A_W3] = tws[j, 2] + w2[j], tws[j, 3] + w3[j]
        tail[j, sec.A_XMIN], tail[j, sec.A_XMAX] = txmin[j], txmax[j]
        tail[j, sec.A_VMIN], tail[j, sec.A_VMAX] = tvmin[j], tvmax[j]
        tail[j, sec.A_FMAX], tail[j, sec.A_STICK] = tfmax[j], tstk[j]
        wj[0], wj[1], wj[2], wj[3] = tot[j, 0] + w0[j], tot[j, 1] + w1[j], tot[j, 2] + w2[j], tot[j, 3] + w3[j]
        sec.mark(fin[j], n_steps * dt, x[j], v[j], wj)
        fin[j, sec.A_E0] = 0.5 * (x0[j] * x0[j] + v0[j] * v0[j])
        fin[j, sec.A_XEND], fin[j, sec.A_VEND] = x[j], v[j]


def run_batch(law, zeta, vb, p, x0, v0, dt, n_steps, t_tail, rec, nrec, tail, fin) -> None:
    """Integrate every lane for ``n_steps``; fills ``rec`` (B, K, NF), ``nrec``, ``tail``, ``fin``. Blocks run in parallel."""
    over_points(_blocks, (len(zeta) + LANES - 1) // LANES, law, zeta, vb, p, x0, v0, dt, n_steps, t_tail, rec, nrec, tail, fin)


@njit(cache=True, nogil=True)
def _blocks(b0, b1, law, zeta, vb, p, x0, v0, dt, n_steps, t_tail, rec, nrec, tail, fin):
    """Blocks ``b0 .. b1-1`` of ``LANES`` lanes each."""
    n = len(zeta)
    for b in range(b0, b1):
        s = b * LANES
        e = min(n, s + LANES)
        _block(law, zeta[s:e], vb[s:e], p[s:e], x0[s:e], v0[s:e], dt, n_steps, t_tail, rec[s:e], nrec[s:e], tail[s:e], fin[s:e])


_warm = False


def warm_up() -> None:
    """Compile (or load from the cache) the batched kernels with wide vectors, once per process."""
    global _warm
    if _warm:
        return

    z = np.zeros(1)
    p = np.zeros((1, N_PARAMS))
    rec = np.full((1, 2, sec.NF), np.nan)
    nrec = np.zeros(1, np.int64)
    tail = np.full((1, sec.NA), np.nan)
    fin = np.full((1, sec.NA), np.nan)
    with wide_vectors():
        _blocks(0, 1, 0, z, z, p, z, z, 1e-3, 1, 0.0, rec, nrec, tail, fin)
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
    over_points(_summarize, len(nrec), rec, nrec, tail, fin, vb, fd, rtol, min_periods, h, fixed_step, noise, out)
    return out


@njit(cache=True, nogil=True)
def _summarize(j0, j1, rec, nrec, tail, fin, vb, fd, rtol, min_periods, h, fixed_step, noise, out):
    for j in range(j0, j1):
        r = unroll(rec[j], nrec[j])
        scale = sec.scale_of(r, tail[j], vb[j], fd[j])
        c = sec.classify(r, tail[j], scale, rtol, min_periods, h, fixed_step, noise * scale)
        s = sec.window_summary(r, tail[j], fin[j], c, fd[j], vb[j])
        for q in range(sec.NC):
            out[j, q] = c[q]
        for q in range(sec.NS):
            out[j, sec.NC + q] = s[q]
