"""The work of each element over a stretch of a phase: Gauss-Legendre on subintervals, exact to rounding.

Channels, in order: springs, dampers, forces (the work each does on the
structure), then per contact the belt's input F_j b_j and then per contact the
interface heat F_j V_r,j (>= 0).  The power of each is a polynomial in the
phase's exponentials e^{lam tau}, e^{+-i Omega tau} (and tau, at a zero
eigenvalue or a resonance), with exponents of modulus at most
mu = 2 max|lam| + 2 max Omega.  A decaying mode that has died (:data:`.phase.DEAD`:
its factor below 1.3e-24 of its size at the phase's start) is left out of mu from
then on, so a stretch is cut where a mode dies: a stiff damper's mode would
otherwise set the node count of a long phase.  Gauss-Legendre with m nodes on a
subinterval of length h integrates e^{mu s} with the error h^(2m+1) (m!)^4 |mu|^(2m) /
((2m+1) ((2m)!)^3) e^{|mu| h} -- relative to the integral, C_m (mu h)^(2m) e^{mu h}
with C_4 = 5.6e-10, C_6 = 1.9e-16, C_8 = 1.7e-23, C_16 = 3.2e-55, C_32 = 3.6e-128;
subintervals of mu h <= 0.1, 0.7, 2, 10 and 30 (m = 4, 6, 8, 16, 32) leave it below
1e-17, so the balance KE + PE = sum of the works closes to rounding.  Each stretch
uses the rule with the fewest nodes in all (a short stretch the 4-node one, a long
one the 32-node one): a chain of ten masses switches every few tenths of its
fastest period, and most of its phases need fewer than 8 nodes.

At the nodes: z from a Taylor form about each subinterval's midpoint (one
exponential per subinterval, one series per pair of symmetric nodes:
:func:`modal_nodes`), and every sum over the nonzeros of its row only
(:data:`Pattern`: a chain's spring touches one or two coordinates, its
dampers, contacts and stuck directions one), which leaves the dense sums' bits.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..layout import FD, STICK
from ..options import NO_RUNTIME
from .phase import free_value, live_rate, modal_raw, next_death, state_raw
from .spectral import SERIES, phi2_pair

#: mu h per subinterval of each rule: C_m (mu h)^(2m) e^{mu h} <= 1e-17 of the integral
MU_H4 = 0.1
MU_H6 = 0.7
MU_H = 2.0
MU_H16 = 10.0
MU_H32 = 30.0
NODES4, WEIGHTS4 = (a.copy() for a in np.polynomial.legendre.leggauss(4))
NODES6, WEIGHTS6 = (a.copy() for a in np.polynomial.legendre.leggauss(6))
NODES, WEIGHTS = (a.copy() for a in np.polynomial.legendre.leggauss(8))
NODES16, WEIGHTS16 = (a.copy() for a in np.polynomial.legendre.leggauss(16))
NODES32, WEIGHTS32 = (a.copy() for a in np.polynomial.legendre.leggauss(32))

#: the nonzeros of a set of rows: ``count[i]`` of row i, at the columns ``cols[i, :count[i]]`` in index order.
#: A sum over them adds the dense sum's terms in its order less its exact zeros (0 x finite): the same bits
Pattern = namedtuple("Pattern", "count cols")
#: :func:`accumulate`'s room: the channels' powers, the contact forces, z, z at each node of a subinterval, q, q'
#: and the held forces' sums;
#: ``ready`` [0] once the Assembly's patterns are filled (at the first use): the elements' direction rows
#: (row = channel), the normal loads' q rows, the contacts' directions, C and K_eff's columns per row (``held``);
#: per combination HE's rows and the columns they use (``need``: one row)
Room = namedtuple("Room", "p f z zg q v rest ready elements normal contact held he need")


def n_channels(asm) -> int:
    """How many work channels the structure has."""
    return len(asm.spring_k) + len(asm.damper_c) + len(asm.force_amp) + 2 * len(asm.belt)


@njit(cache=True, inline="always")
def dot_row(a, i, x):
    """a[i] . x summed in index order, without a view of the row or a BLAS call (it runs at every node)."""
    s = 0.0
    for b in range(len(x)):
        s += a[i, b] * x[b]
    return s


@njit(cache=True, inline="always")
def element_powers(elastic, forcing, q, v, t, out):
    """The springs', dampers' and forces' powers into ``out``; ``elastic`` = (k, spring dirs, c, damper dirs)."""
    sk, sd, dcs, dd = elastic
    fa, fo, fp, fdir = forcing
    c = 0
    for s in range(len(sk)):
        out[c] = -sk[s] * dot_row(sd, s, q) * dot_row(sd, s, v)
        c += 1
    for d in range(len(dcs)):
        w = dot_row(dd, d, v)
        out[c] = -dcs[d] * w * w
        c += 1
    for i in range(len(fa)):
        out[c] = fa[i] * math.cos(fo[i] * t + fp[i]) * dot_row(fdir, i, v)
        c += 1
    return c


@njit(cache=True, inline="always")
def contact_powers(belt, cd, modes, f, v, c, out):
    """Each contact's belt input F_j b_j and interface heat F_j V_r,j into ``out`` from channel ``c`` on."""
    k = len(belt)
    for j in range(k):
        out[c + j] = f[j] * belt[j]
        out[c + k + j] = 0.0 if modes[j] == STICK else f[j] * (belt[j] - dot_row(cd, j, v))


@njit(cache=True)
def rule(x):
    """(nodes, weights, subintervals) of the Gauss-Legendre rule with the fewest nodes over a stretch of mu h = x."""
    if x <= MU_H4:  # one subinterval of the smaller rules, before any of the larger ones
        return NODES4, WEIGHTS4, 1
    if x <= MU_H6:
        return NODES6, WEIGHTS6, 1
    n8, n16, n32 = max(1, math.ceil(x / MU_H)), max(1, math.ceil(x / MU_H16)), max(1, math.ceil(x / MU_H32))
    if 8 * n8 <= 16 * n16 and 8 * n8 <= 32 * n32:
        return NODES, WEIGHTS, n8
    if 16 * n16 <= 32 * n32:
        return NODES16, WEIGHTS16, n16
    return NODES32, WEIGHTS32, n32


@njit(cache=True)
def integrate(asm, cb, ph, om, ta, tb, acc):
    """Add each channel's work over [ta, tb] of the phase (local times) to ``acc``."""
    if tb - ta <= 0.0:
        return
    accumulate(asm, cb, ph, om, ta, tb, acc, new_room(len(acc), len(asm.belt), len(cb.lam), len(asm.q0)))


@njit(cache=True)
def new_pattern(rows, n):
    """An empty :data:`Pattern` of ``rows`` rows of up to ``n`` nonzeros."""
    return Pattern(np.zeros(rows, dtype=np.int32), np.zeros((rows, n), dtype=np.int32))


@njit(cache=True)
def new_room(n_work, k, m, n):
    """The :data:`Room` of :func:`accumulate` for ``n_work`` channels, ``k`` contacts, ``m`` modal coordinates and
    ``n`` coordinates; its patterns are filled at its first use (a room serves one Assembly)."""
    return Room(np.empty(n_work), np.empty(k), np.empty(m, dtype=np.complex128),
                np.empty((len(NODES32), m), dtype=np.complex128), np.empty(n), np.empty(n),
                np.empty(n), np.zeros(1, dtype=np.int8), new_pattern(n_work, n), new_pattern(k, n),
                new_pattern(k, n), new_pattern(n, n), new_pattern(k, n), new_pattern(np.int64(1), n))


@njit(cache=True, inline="always")
def fill_rows(a, first, offset, pat):
    """Pattern rows ``first``, ... of the rows of ``a`` (their nonzeros from column ``offset`` on, as offsets)."""
    for i in range(a.shape[0]):
        c = 0
        for b in range(a.shape[1] - offset):
            if a[i, offset + b] != 0.0:
                pat.cols[first + i, c] = b
                c += 1
        pat.count[first + i] = c


@njit(cache=True, inline="always")
def fill_held(asm, pat):
    """Row i of ``pat``: the columns where C or K_eff can be nonzero.  K_eff = K - sum_j sigma_j F_d,j e_j n_j^T
    (:mod:`.combo`): outside K's nonzeros and the e_j n_j^T of the loads that depend on q it is an exact 0."""
    cd, normal = asm.contact_dir, asm.normal
    n = len(asm.q0)
    for i in range(n):
        c = 0
        for b in range(n):
            hit = asm.damping[i, b] != 0.0 or asm.stiffness[i, b] != 0.0
            for j in range(len(asm.belt)):
                hit = hit or (cd[j, i] != 0.0 and normal[j, 1 + b] != 0.0)
            if hit:
                pat.cols[i, c] = b
                c += 1
        pat.count[i] = c


@njit(cache=True, inline="always")
def fill_assembly(asm, room):
    """The Assembly's patterns into ``room``: the elements' direction rows (springs, dampers, forces: row = channel),
    the normal loads' q rows, the contacts' directions and C, K_eff's columns per row."""
    ns, nd = len(asm.spring_k), len(asm.damper_c)
    fill_rows(asm.spring_dir, 0, 0, room.elements)
    fill_rows(asm.damper_dir, ns, 0, room.elements)
    fill_rows(asm.force_dir, ns + nd, 0, room.elements)
    fill_rows(asm.normal, 0, 1, room.normal)
    fill_rows(asm.contact_dir, 0, 0, room.contact)
    fill_held(asm, room.held)
    room.ready[0] = 1


@njit(cache=True, inline="always")
def fill_combination(cb, room):
    """HE's rows into ``room.he`` and the columns any of them uses (the held forces' sums needed) into
    ``room.need`` (Z's and R's columns are the combination's own pattern, :mod:`.sparsity`)."""
    he = cb.HE
    fill_rows(he, 0, 0, room.he)
    need = room.need
    c = 0
    for b in range(he.shape[1]):
        for s in range(he.shape[0]):
            if he[s, b] != 0.0:
                need.cols[0, c] = b
                c += 1
                break
    need.count[0] = c


@njit(cache=True, inline="always")
def sparse_dot(a, i, pat, r, x):
    """a[i] . x over pattern row ``r`` (a[i]'s nonzeros, in index order): :func:`dot_row` without its exact zeros."""
    s = 0.0
    for p in range(pat.count[r]):
        b = pat.cols[r, p]
        s += a[i, b] * x[b]
    return s


@njit(cache=True, inline="always")
def node_state(vm, zm, rm, nz, u0, bs, tau, zg, g, room):
    """(q, q') at a node into ``room.q``, ``room.v`` from z = ``zg[g]`` (:func:`.phase.state_raw` on a copy of that
    row in ``room.z``: a row taken as a view would need numba's runtime here)."""
    z = room.z
    for a in range(vm.shape[1]):
        z[a] = zg[g, a]
    state_raw(vm, zm, rm, nz, u0, bs, tau, z, room.q, room.v)


@njit(cache=True, inline="always")
def sparse_element_powers(elastic, forcing, pat, q, v, t, out):
    """:func:`element_powers` over the elements' pattern (row = channel)."""
    sk, sd, dcs, dd = elastic
    fa, fo, fp, fdir = forcing
    c = 0
    for s in range(len(sk)):
        out[c] = -sk[s] * sparse_dot(sd, s, pat, c, q) * sparse_dot(sd, s, pat, c, v)
        c += 1
    for d in range(len(dcs)):
        w = sparse_dot(dd, d, pat, c, v)
        out[c] = -dcs[d] * w * w
        c += 1
    for i in range(len(fa)):
        out[c] = fa[i] * math.cos(fo[i] * t + fp[i]) * sparse_dot(fdir, i, pat, c, v)
        c += 1
    return c


@njit(cache=True, inline="always")
def sparse_slip_forces(normal, law, modes, pat, q, f):
    """The slipping contacts' friction forces +-F_d N_j into ``f`` (N_j over the normal loads' pattern)."""
    for j in range(len(f)):
        if modes[j] != STICK:
            nj = normal[j, 0]
            for p in range(pat.count[j]):
                b = pat.cols[j, p]
                nj += normal[j, 1 + b] * q[b]
            f[j] = modes[j] * law[j, FD] * nj


@njit(cache=True, inline="always")
def sparse_held_forces(damping, keff, f0, he, stuck, forcing, room, q, v, t):
    """The stuck contacts' held forces HE (C q' + K_eff q - f0 - forces(t)) into ``room.f`` (``forcing`` = (amp,
    omega, phi, dir)): the sums over the patterns, and ``room.rest`` = C q' + ... only in the rows HE uses."""
    fa, fo, fp, fdir = forcing
    rest, need, held = room.rest, room.need, room.held
    for p in range(need.count[0]):
        i = need.cols[0, p]
        x = -f0[i]
        for a in range(held.count[i]):
            b = held.cols[i, a]
            x += damping[i, b] * v[b] + keff[i, b] * q[b]
        rest[i] = x
    for g in range(len(fa)):
        c = fa[g] * math.cos(fo[g] * t + fp[g])
        for p in range(need.count[0]):
            i = need.cols[0, p]
            rest[i] -= fdir[g, i] * c
    for s in range(len(stuck)):
        room.f[stuck[s]] = sparse_dot(he, s, room.he, s, rest)


@njit(cache=True, inline="always")
def sparse_contact_powers(belt, cd, modes, pat, f, v, c, out):
    """:func:`contact_powers` over the contacts' pattern."""
    k = len(belt)
    for j in range(k):
        out[c + j] = f[j] * belt[j]
        out[c + k + j] = 0.0 if modes[j] == STICK else f[j] * (belt[j] - sparse_dot(cd, j, pat, j, v))


@njit(cache=True, inline="always")
def modal_nodes(lam, ph, mid, half, nodes, zg):
    """z at the nodes mid + half x_g into ``zg[g]`` (a phase without harmonic terms).

    z' = lam z + b0 + b1 tau gives z''' = lam z'', so about the midpoint z(mid + s) = z + s z' + s^2 z''
    phi2(lam s) (z, z', z'' at mid): one exponential per subinterval and one series per pair of nodes
    (:func:`.spectral.phi2_pair`: s and -s) instead of an exponential and a series per node.  Where
    |lam s| >= SERIES the nodes take :func:`free_value`.  The nodes are symmetric (numpy's leggauss).
    """
    z0, b0, b1 = ph.z0, ph.b0, ph.b1
    m = len(nodes)
    for a in range(len(lam)):
        la = lam[a]
        za = free_value(la, mid, z0[a], b0[a], b1[a])
        d1 = la * za + (b0[a] + b1[a] * mid)
        d2 = la * d1 + b1[a]
        if m % 2:
            zg[m // 2, a] = za
        for g in range(m // 2):
            s = half * nodes[m - 1 - g]
            w = la * s
            if w.real * w.real + w.imag * w.imag < SERIES * SERIES:
                pa, pb = phi2_pair(w)
                zg[m - 1 - g, a] = za + s * d1 + s * s * d2 * pa
                zg[g, a] = za - s * d1 + s * s * d2 * pb
            else:
                zg[m - 1 - g, a] = free_value(la, mid + half * nodes[m - 1 - g], z0[a], b0[a], b1[a])
                zg[g, a] = free_value(la, mid + half * nodes[g], z0[a], b0[a], b1[a])


@njit(cache=True, inline="always")
def harmonic_nodes(lam, ph, om, mid, half, nodes, z, zg):
    """z at the nodes into ``zg[g]`` with harmonic terms (:func:`.phase.modal_raw` at each; ``z``: room)."""
    for g in range(len(nodes)):
        modal_raw(lam, ph.z0, ph.b0, ph.b1, ph.bh, ph.theta, om, mid + half * nodes[g], z)
        for a in range(len(z)):
            zg[g, a] = z[a]


@njit(cache=True, inline="always")
def node_powers(asm, cb, ph, tau, g, room):
    """Every channel's power at the node ``tau`` (z in ``room.zg[g]``) into ``room.p``."""
    p, f = room.p, room.f
    forcing = (asm.force_amp, asm.force_omega, asm.force_phi, asm.force_dir)
    node_state(cb.V, cb.Z, cb.R, cb.nz, ph.u0, ph.bs, tau, room.zg, g, room)
    c = sparse_element_powers((asm.spring_k, asm.spring_dir, asm.damper_c, asm.damper_dir), forcing, room.elements,
                              room.q, room.v, ph.t0 + tau, p)
    sparse_slip_forces(asm.normal, asm.law, cb.modes, room.normal, room.q, f)
    if len(cb.stuck):
        sparse_held_forces(asm.damping, cb.keff, cb.f0, cb.HE, cb.stuck, forcing, room, room.q, room.v, ph.t0 + tau)
    sparse_contact_powers(asm.belt, asm.contact_dir, cb.modes, room.contact, f, room.v, c, p)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted at the nodes
def accumulate(asm, cb, ph, om, ta, tb, acc, room):
    """:func:`integrate` in the :data:`Room` ``room``."""
    if room.ready[0] == 0:
        fill_assembly(asm, room)
    fill_combination(cb, room)
    while ta < tb:  # a stretch per set of live modes: a dead mode's exponent no longer sets the node count
        t1 = min(tb, next_death(cb.lam, ta))
        gauss(asm, cb, ph, om, ta, t1, acc, room)
        ta = t1


@njit(cache=True, **NO_RUNTIME)
def gauss(asm, cb, ph, om, ta, tb, acc, room):
    """:func:`accumulate` over [ta, tb], where the same modes live throughout."""
    span = tb - ta
    nodes, weights, nsub = rule(span * 2.0 * live_rate(cb.lam, om, ta))
    h = span / nsub
    p, zg = room.p, room.zg
    for s in range(nsub):
        mid = ta + (s + 0.5) * h
        if ph.bh.shape[1]:
            harmonic_nodes(cb.lam, ph, om, mid, 0.5 * h, nodes, room.z, zg)
        else:
            modal_nodes(cb.lam, ph, mid, 0.5 * h, nodes, zg)
        for g in range(len(nodes)):
            node_powers(asm, cb, ph, mid + 0.5 * h * nodes[g], g, room)
            for c in range(len(acc)):
                acc[c] += 0.5 * h * weights[g] * p[c]
