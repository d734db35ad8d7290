"""A phase: one mode combination from a start state; its closed form and its event functions at any time.

In modal coordinates z = V^-1 (y, y') the reduced equations decouple:
z_m' = lam_m z_m + beta_m(tau), beta = b0 + b1 tau + sum_i bh_i cos(theta_i + Omega_i tau)
(tau: the time since the phase's start t0, theta_i = Omega_i t0 + phi_i), so

    z_m(tau) = e^{lam tau} z_m(0) + tau phi1(lam tau) b0_m + tau^2 phi2(lam tau) b1_m
               + sum_i bh_mi (e^{i theta} expint(lam, i Omega, tau) + e^{-i theta} expint(lam, -i Omega, tau)) / 2

(:mod:`.spectral`).  Every event function is g(tau) = Re(W z(tau)) + e0 + e1 tau
+ sum_i Dh_i cos(theta_i + Omega_i tau), and the state Re(V z(tau)) through Z.
The modes m are the combination's kept roots: one of each conjugate pair on
the real-mode route, its columns of V and W doubled (:mod:`.combo`), so that
these real parts and the bounds below, sums of |W_m| |z_m|, count the pair.

:func:`bound` bounds |g^(p)| (p = 2, 3) on [a, a + h] from the modal amplitudes:
|z_m(s)| <= e^{max(Re lam, 0) h} (|z_m(a)| + h max|beta_m|), and
z^(p) = lam^p z + sum_{i < p} lam^(p-1-i) beta^(i); for a decaying mode also
from its rates at the phase's start (:func:`rates_into`), whichever is less.
"""

from __future__ import annotations

import cmath
import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..options import NO_RUNTIME
from ..products import add_product
from . import sparsity as sp
from .spectral import expint, phis

Phase = namedtuple("Phase", "t0 z0 b0 b1 bh theta e0 e1 u0 bs")
#: the moduli the walk's bounds take, as real arrays: |z(a)| at the current interval's start (rewritten per
#: interval) and the phase's |b0|, |b1|, |bh|, |lam| (complex moduli are hypot calls: not in the loops); |z'(0)|
#: and |z''(0)| of the decaying modes, each less its forcing's part (:func:`rates_into`; the others' entries are
#: not read)
Mags = namedtuple("Mags", "z b0 b1 bh lam w u")


@njit(cache=True)
def start(cb, asm, q, v, t0):
    """The :data:`Phase` of combination ``cb`` from the state (q, q') = (``q``, ``v``) at time ``t0``, in new arrays
    (:func:`start_in` in a room of its own)."""
    return start_in(cb, asm, q, v, t0, start_room(len(q), len(asm.belt), len(asm.force_omega)))


@njit(cache=True, inline="always")
def modal_into(cb, ph, om, tau, z):
    """z(tau) into ``z``: the modal coordinates ``tau`` after the phase's start (``om``: the forces' Omega)."""
    modal_raw(cb.lam, ph.z0, ph.b0, ph.b1, ph.bh, ph.theta, om, tau, z)


@njit(cache=True, inline="always")
def modal_raw(lams, z0, b0, b1, bh, theta, om, tau, z):
    """:func:`modal_into` from the arrays themselves (a loop that binds no record runs no reference counting)."""
    for a in range(len(lams)):
        lam = lams[a]
        s = free_value(lam, tau, z0[a], b0[a], b1[a])
        for f in range(len(om)):
            w = 1j * om[f]
            ep = cmath.exp(1j * theta[f])
            s += 0.5 * bh[a, f] * (ep * expint(lam, w, tau) + ep.conjugate() * expint(lam, -w, tau))
        z[a] = s


@njit(cache=True, inline="always")
def free_value(lam, tau, z0, b0, b1):
    """One modal coordinate without harmonic terms: e^{lam tau} z0 + tau phi1 b0 + tau^2 phi2 b1."""
    e, p1, p2 = phis(lam, tau)
    return e * z0 + p1 * b0 + p2 * b1


@njit(cache=True)
def modal_at(cb, ph, om, tau):
    """z(tau), a new array (:func:`modal_into`)."""
    z = np.empty(len(cb.lam), dtype=np.complex128)
    modal_fill(cb, ph, om, tau, z)
    return z


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def modal_fill(cb, ph, om, tau, z):
    """:func:`modal_into`, compiled on its own."""
    modal_into(cb, ph, om, tau, z)


@njit(cache=True, inline="always")
def state_into(cb, ph, tau, z, q, v):
    """(q, q') at ``tau`` into ``q``, ``v`` from z = z(tau): Re(V z) through Z, plus the stuck directions' part."""
    state_raw(cb.V, cb.Z, cb.R, cb.nz, ph.u0, ph.bs, tau, z, q, v)


@njit(cache=True, inline="always")
def state_raw(vm, zm, rm, nz, u0, bs, tau, z, q, v):
    """:func:`state_into` from the arrays themselves (V, Z, R, the combination's pattern ``nz``, u0, b_S): the
    sums through Z and R over their columns' nonzeros (:mod:`.sparsity`)."""
    n, r = zm.shape
    for i in range(n):
        q[i], v[i] = 0.0, 0.0
    zc, rc = nz[0, sp.ZC], nz[0, sp.RC]
    for a in range(2 * r):
        x = 0.0
        for b in range(vm.shape[1]):  # V's columns: one per root kept (:mod:`.combo`: a conjugate pair's once)
            x += (vm[a, b] * z[b]).real
        col, out = (a, q) if a < r else (a - r, v)
        for p in range(nz[zc + col, 0]):
            i = nz[zc + col, 1 + p]
            out[i] += zm[i, col] * x
    for s in range(len(u0)):
        u = u0[s] + bs[s] * tau
        for p in range(nz[rc + s, 0]):
            i = nz[rc + s, 1 + p]
            q[i] += rm[i, s] * u
            v[i] += rm[i, s] * bs[s]


@njit(cache=True)
def state_at(cb, ph, om, tau):
    """(q, q') at ``tau`` after the phase's start, new arrays."""
    n = cb.Z.shape[0]
    q, v = np.empty(n), np.empty(n)
    state_fill(cb, ph, om, tau, np.empty(len(cb.lam), dtype=np.complex128), q, v)
    return q, v


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def state_fill(cb, ph, om, tau, z, q, v):
    """(q, q') at ``tau`` into ``q``, ``v`` (``z``: room for z(tau))."""
    modal_into(cb, ph, om, tau, z)
    state_into(cb, ph, tau, z, q, v)


@njit(cache=True, inline="always")
def harmonic(dh_row, ph, om, tau, order):
    """sum_i Dh_i d^order/dtau^order cos(theta_i + Omega_i tau)."""
    s = 0.0
    for f in range(len(om)):
        arg = ph.theta[f] + om[f] * tau
        c = math.cos(arg) if order % 2 == 0 else math.sin(arg)
        sign = 1.0 if order % 4 in (0, 3) else -1.0
        s += dh_row[f] * sign * om[f] ** order * c
    return s


@njit(cache=True, inline="always")
def event_raw(e0, e1, dh, w, theta, om, e, tau, z):
    """Event function ``e`` at ``tau`` (``z`` = z(tau)) from the phase's and the combination's arrays.

    Arrays, not the records: a record passed in the walk's loops costs the reference counting of all its arrays.
    """
    h = 0.0
    for f in range(len(om)):
        h += dh[e, f] * math.cos(theta[f] + om[f] * tau)
    s = e0[e] + e1[e] * tau + h
    for a in range(len(z)):
        s += (w[e, a] * z[a]).real
    return s


@njit(cache=True, inline="always")
def beta_mode(ph, om, m, tau):
    """(beta_m(tau), beta_m'(tau)): mode m's forcing and its rate."""
    b, db = ph.b0[m] + ph.b1[m] * tau, ph.b1[m] + 0.0j
    for f in range(len(om)):
        arg = ph.theta[f] + om[f] * tau
        b += ph.bh[m, f] * math.cos(arg)
        db -= ph.bh[m, f] * om[f] * math.sin(arg)
    return b, db


@njit(cache=True, inline="always")
def event_rate(cb, ph, om, e, tau, z, order):
    """d^order g_e / dtau^order at ``tau`` (order 1 or 2; ``z`` = z(tau))."""
    s = harmonic(cb.Dh[e], ph, om, tau, order) + (ph.e1[e] if order == 1 else 0.0)
    for a in range(len(z)):
        if cb.W[e, a] == 0.0:
            continue
        lam = cb.lam[a]
        b, db = beta_mode(ph, om, a, tau)
        d = lam * z[a] + b
        if order == 2:
            d = lam * d + db
        s += (cb.W[e, a] * d).real
    return s


@njit(cache=True, inline="always")
def magnitudes_into(cb, ph, mg):
    """The phase's moduli into the :data:`Mags` ``mg`` (all but ``mg.z``, which the walk fills per interval)."""
    abs_into(ph.b0, mg.b0)
    abs_into(ph.b1, mg.b1)
    abs_into(cb.lam, mg.lam)
    for m in range(ph.bh.shape[0]):
        for f in range(ph.bh.shape[1]):
            mg.bh[m, f] = abs(ph.bh[m, f])


@njit(cache=True, inline="always")
def abs_into(z, out):
    """|z| elementwise into ``out``."""
    for i in range(len(z)):
        out[i] = abs(z[i])


@njit(cache=True, inline="always")
def growth(rate, h):
    """e^{max(rate, 0) h} (1 for a decaying mode, without the exponential)."""
    return math.exp(rate * h) if rate > 0.0 else 1.0


@njit(cache=True, inline="always")
def beta_bounds(mg, om, m, tmax):
    """(|beta_m|, |beta_m'|, |beta_m''|, |beta_m'''|) bounded over [0, tmax] from the phase's magnitudes ``mg``."""
    b0, b1, b2, b3 = mg.b0[m] + mg.b1[m] * tmax, mg.b1[m], 0.0, 0.0
    for f in range(len(om)):
        c = mg.bh[m, f]
        b0, b1, b2, b3 = b0 + c, b1 + c * om[f], b2 + c * om[f] ** 2, b3 + c * om[f] ** 3
    return b0, b1, b2, b3


@njit(cache=True, inline="always")
def mode_term(cb, om, mg, m, a, h, order):
    """Mode m's term of :func:`bound` of ``order`` over [a, a + h], before the weight |W[e, m]|, and the same from
    |z(a)| alone (the size of the terms g^(order) is computed from, for its rounding): for a decaying mode the
    smaller of that and the bound from its start (:func:`rates_into`)."""
    b0, b1, b2, b3 = beta_bounds(mg, om, m, abs(a) + h)
    lam = cb.lam[m]
    zb = growth(lam.real, h) * (mg.z[m] + h * b0)
    al = mg.lam[m]
    if order == 2:
        dz, w0, bk = al * al * zb + al * b0 + b1, mg.w[m], b2
    else:
        dz, w0, bk = al ** 3 * zb + al * al * b0 + al * b1 + b2, mg.u[m], b3
    if lam.real >= 0.0:
        return dz, dz
    fade = FADE if a >= lifetime(lam.real) else 1.0
    return min(dz, al * fade * w0 + bk / -lam.real), dz


@njit(cache=True, inline="always")
def bound(cb, om, e, a, h, mg, order):
    """A bound on |g_e^(order)| over [a, a + h] (order 2 or 3) from the modal amplitudes ``mg.z`` = |z(a)|."""
    s = 0.0
    for f in range(len(om)):
        s += abs(cb.Dh[e, f]) * om[f] ** order
    for m in range(len(mg.z)):
        w = cb.WA[e, m]
        if w == 0.0:
            continue
        s += w * mode_term(cb, om, mg, m, a, h, order)[0]
    return s


@njit(cache=True, inline="always")
def mode_bounds(cb, om, a, h, mg, out, crude):
    """Each mode's terms of :func:`bound` of order 2 (before the weight |W[e, m]|) into ``out``, and from |z(a)|
    alone into ``crude`` (:func:`mode_term`): once per interval."""
    for m in range(len(out)):
        out[m], crude[m] = mode_term(cb, om, mg, m, a, h, 2)


@njit(cache=True, inline="always")
def bound_of(cb, om, e, dz):
    """:func:`bound` of order 2 from the modes' terms ``dz`` (:func:`mode_bounds`), summed in the same order."""
    s = 0.0
    dh, wa = cb.Dh, cb.WA
    for f in range(len(om)):
        s += abs(dh[e, f]) * om[f] ** 2
    for m in range(len(dz)):
        w = wa[e, m]
        if w == 0.0:
            continue
        s += w * dz[m]
    return s


@njit(cache=True, inline="always")
def fixed_size(cb, ph, e, tau):
    """|e0| + |e1 tau| + sum |Dh|: the terms of event function ``e`` that are not modal."""
    dh = cb.Dh
    sh = 0.0  # |Dh_e| summed in order, as np.abs(row).sum() would, without making that array
    for f in range(dh.shape[1]):
        sh += abs(dh[e, f])
    return abs(ph.e0[e]) + abs(ph.e1[e] * tau) + sh


@njit(cache=True, inline="always")
def size_of(cb, ph, e, tau, az):
    """The sum of the magnitudes of event function ``e``'s terms at ``tau``, its rounding a few EPS of it, from the
    moduli ``az`` = |z(tau)| (computed once for all functions: no complex moduli per function)."""
    s, wa = fixed_size(cb, ph, e, tau), cb.WA
    for a in range(len(az)):
        s += wa[e, a] * az[a]
    return s


#: a decaying mode whose factor e^{Re(lam) tau} has fallen below e^-DEAD (1.3e-24) no longer sets a time scale:
#: its terms are that far below what they were at the phase's start (a stiff damper's overdamped mode dies
#: within a few of its own time constants, while the phase runs on at the slow modes' pace)
DEAD = 55.0
#: e^{Re(lam) tau} from a mode's death on, bounded with room for the rounding of :func:`lifetime`
FADE = 2.0 * math.exp(-DEAD)


@njit(cache=True, inline="always")
def lifetime(re):
    """When a mode of rate Re(lam) = ``re`` dies (:data:`DEAD`): alive at tau < lifetime; inf: never."""
    return -DEAD / re if re < 0.0 else math.inf


@njit(cache=True, inline="always")
def live_rate(lam, om, tau):
    """max |lam| over the modes alive at ``tau`` (:func:`lifetime`) + max Omega (0 for none of either): the
    phase's fastest time scale's rate there, without numba's runtime (the walk's longest interval and the work
    quadrature's node count both follow it)."""
    m = 0.0
    for i in range(len(lam)):
        if tau < lifetime(lam[i].real):
            m = max(m, abs(lam[i]))
    if len(om) == 0:
        return m + 0.0
    w = om[0]
    for i in range(1, len(om)):
        w = max(w, om[i])
    return m + w


@njit(cache=True, inline="always")
def longest(lam, om, tau, span):
    """The walk's longest interval from ``tau`` on: 1 / :func:`live_rate`, at most ``span``."""
    rate = live_rate(lam, om, tau)
    return span if rate == 0.0 else min(span, 1.0 / rate)


@njit(cache=True, inline="always")
def next_death(lam, tau):
    """The time after ``tau`` when the next mode alive at ``tau`` dies (:func:`lifetime`); inf: none."""
    until = math.inf
    for i in range(len(lam)):
        life = lifetime(lam[i].real)
        if tau < life:
            until = min(until, life)
    return until


@njit(cache=True, inline="always")
def rates_into(cb, ph, om, mg):
    """|w_1(0)| and |w_2(0)| into ``mg.w``, ``mg.u`` for the decaying modes, w_k = z^(k) + beta^(k) / lam: what
    bounds their z^(k+1) over the phase (:func:`mode_term`).

    y = z^(k) solves y' = lam y + beta^(k), so w_k solves w' = lam w + beta^(k+1) / lam and z^(k+1) = y' = lam w_k:
    |z^(k+1)(s)| <= |lam| e^{Re(lam) s} |w_k(0)| + max|beta^(k+1)| / |Re(lam)|, the factor e^{Re(lam) s} at most 1,
    or :data:`FADE` once the mode is dead.  The bound from |z(a)| multiplies the mode's forced value by |lam|^2:
    a fast overdamped mode on its forcing (a stiff damper's, from a phase's start when the stiff element barely
    moves, or once it has settled) has |z''| far below that, and a bound |lam| / |Re(lam)| times its size would hold
    the walk's intervals to its time scale, or below the shortest one (a run then ended "stuck" on a touch that
    never was).
    """
    for m in range(len(mg.w)):
        lam = cb.lam[m]
        if lam.real < 0.0:
            b, db = beta_mode(ph, om, m, 0.0)
            d2b = 0.0j
            for f in range(len(om)):
                d2b -= ph.bh[m, f] * om[f] ** 2 * math.cos(ph.theta[f])
            d = lam * ph.z0[m] + b
            mg.w[m], mg.u[m] = abs(d + db / lam), abs(lam * d + db + d2b / lam)


#: room for :func:`start_in`, made once per run (:func:`start_room`): the phase's z0, b0 (room for 2n modes),
#: theta (one per force), e0 (one per event slot), u0 (one per contact), and R u0, the projected force and x for the
#: products
StartRoom = namedtuple("StartRoom", "z0 b0 theta e0 u0 ru f x p0")


@njit(cache=True)
def start_room(n, k, nf):
    """A :data:`StartRoom` for ``n`` coordinates, ``k`` contacts (three event slots each) and ``nf`` forces."""
    c = np.complex128
    return StartRoom(np.zeros(2 * n, dtype=c), np.zeros(2 * n, dtype=c), np.zeros(nf), np.zeros(3 * k), np.zeros(k),
                     np.zeros(n), np.zeros(n), np.zeros(2 * n), np.zeros(n))


@njit(cache=True, inline="always")
def start_in(cb, asm, q, v, t0, room):
    """:func:`start` in the :data:`StartRoom` ``room``: its arrays are views of the room's (the next start
    overwrites them)."""
    start_fill(cb, asm, q, v, t0, room)
    m, ns = len(cb.lam), len(cb.stuck)
    return Phase(t0, room.z0[:m], room.b0[:m], cb.b1, cb.bh, room.theta, room.e0, cb.e1, room.u0[:ns], cb.bs)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted
def start_fill(cb, asm, q, v, t0, room):
    """:func:`start`'s arrays into ``room``: products by loops (no temporaries; a start is made at every switch) over
    the combination's patterns (:mod:`.sparsity`) where it has them: Z^T over Z's columns, R u0 by R's columns (each
    row's terms in their order), and the products with R u0 and R b_S over R's nonzero rows (0 elsewhere)."""
    n, ns, nr, m, nz = len(q), len(cb.stuck), cb.Z.shape[1], len(cb.lam), cb.nz
    u0, ru, f, x, p0, zt, rb, rm = room.u0, room.ru, room.f, room.x, room.p0, cb.ZT, cb.rb, cb.R
    for i in range(ns):
        u0[i] = 0.0
        for a in range(n):
            u0[i] += asm.contact_dir[cb.stuck[i], a] * q[a]
    for a in range(n):
        ru[a], f[a] = 0.0, cb.f0[a]
    rc, zc, used = nz[0, sp.RC], nz[0, sp.ZC], nz[0, sp.RU]
    for s in range(ns):
        for p in range(nz[rc + s, 0]):
            i = nz[rc + s, 1 + p]
            ru[i] += rm[i, s] * u0[s]
    for i in range(n):  # the force f0 - C R b_S - K_eff R u0, projected on Z below
        f[i] -= sp.sparse_dot(asm.damping, i, nz, used, rb)
    for i in range(n):
        f[i] -= sp.sparse_dot(cb.keff, i, nz, used, ru)
    for c in range(nr):
        x[c], x[nr + c], p0[c] = 0.0, 0.0, 0.0
        for p in range(nz[zc + c, 0]):  # Z^T's row c: Z's column c
            a = nz[zc + c, 1 + p]
            x[c] += zt[c, a] * (q[a] - ru[a])
            x[nr + c] += zt[c, a] * (v[a] - rb[a])
            p0[c] += zt[c, a] * f[a]
    for a in range(m):
        room.z0[a], room.b0[a] = 0.0, 0.0
    add_product(cb.Vi, x, 1.0, room.z0)
    add_product(cb.VB, p0, 1.0, room.b0)
    for i in range(len(room.theta)):
        room.theta[i] = asm.force_omega[i] * t0 + asm.force_phi[i]
    e0, d = room.e0, cb.D
    for e in range(len(e0)):
        s = 0.0
        for p in range(nz[used, 0]):  # D (R u0, R b_S)
            a = nz[used, 1 + p]
            s += d[e, a] * ru[a] + d[e, n + a] * rb[a]
        e0[e] = cb.dc[e] + s
