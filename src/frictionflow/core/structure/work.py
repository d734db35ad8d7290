"""The work of each element over a stretch of a phase: Gauss-Legendre on subintervals, exact to rounding.

Channels, in order: springs, dampers, forces (the work each does on the
structure), then per contact the belt's input F_j b_j and then per contact the
interface heat F_j V_r,j (>= 0).  The power of each is a polynomial in the
phase's exponentials e^{lam tau}, e^{+-i Omega tau} (and tau, at a zero
eigenvalue or a resonance), with exponents of modulus at most
mu = 2 max|lam| + 2 max Omega.  Gauss-Legendre with m nodes on a subinterval
of length h integrates e^{mu s} with the error h^(2m+1) (m!)^4 |mu|^(2m) /
((2m+1) ((2m)!)^3) e^{|mu| h} -- relative to the integral, C_m (mu h)^(2m) e^{mu h}
with C_4 = 5.6e-10, C_6 = 1.9e-16, C_8 = 1.7e-23, C_16 = 3.2e-55, C_32 = 3.6e-128;
subintervals of mu h <= 0.1, 0.7, 2, 10 and 30 (m = 4, 6, 8, 16, 32) leave it below
1e-17, so the balance KE + PE = sum of the works closes to rounding.  Each stretch
uses the rule with the fewest nodes in all (a short stretch the 4-node one, a long
one the 32-node one): a chain of ten masses switches every few tenths of its
fastest period, and most of its phases need fewer than 8 nodes.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..layout import FD, STICK
from ..options import NO_RUNTIME
from .phase import fastest_rate, modal_raw, state_raw

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
def slip_forces(normal, law, modes, q, f):
    """The slipping contacts' friction forces +-F_d N_j into ``f``."""
    n = len(q)
    for j in range(len(f)):
        if modes[j] != STICK:
            nj = normal[j, 0]
            for i in range(n):
                nj += normal[j, 1 + i] * q[i]
            f[j] = modes[j] * law[j, FD] * nj


@njit(cache=True, inline="always")
def held_forces(damping, keff, f0, he, stuck, forcing, q, v, t, f, rest):
    """The stuck contacts' held forces (dampers included) into ``f``; ``forcing`` = (amp, omega, phi, dir).

    ``rest``: room for C q' + K_eff q - f0 - forces(t), computed once for all the stuck contacts.
    """
    fa, fo, fp, fdir = forcing
    n = len(q)
    for i in range(n):
        x = -f0[i]
        for b in range(n):
            x += damping[i, b] * v[b] + keff[i, b] * q[b]
        rest[i] = x
    for g in range(len(fa)):
        c = fa[g] * math.cos(fo[g] * t + fp[g])
        for i in range(n):
            rest[i] -= fdir[g, i] * c
    for s in range(len(stuck)):
        f[stuck[s]] = dot_row(he, s, rest)


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
def new_room(n_work, k, m, n):
    """Room for :func:`accumulate`: the ``n_work`` channels' powers, ``k`` contact forces, ``m`` modal coordinates,
    q, q' and the held forces' sums (``n`` each)."""
    return (np.empty(n_work), np.empty(k), np.empty(m, dtype=np.complex128), np.empty(n), np.empty(n), np.empty(n))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the records' arrays are not reference-counted at the nodes
def accumulate(asm, cb, ph, om, ta, tb, acc, room):
    """:func:`integrate` in ``room`` = (powers, contact forces, z, q, q', room for the held forces)."""
    span = tb - ta
    mu = 2.0 * fastest_rate(cb.lam, om)
    nodes, weights, nsub = rule(span * mu)
    h = span / nsub
    p, f, z, q, v, rest = room
    lam, vm, zm, rm, modes, stuck, keff, f0, he = cb.lam, cb.V, cb.Z, cb.R, cb.modes, cb.stuck, cb.keff, cb.f0, cb.HE
    z0, b0, b1, bh, theta, u0, bs, t0 = ph.z0, ph.b0, ph.b1, ph.bh, ph.theta, ph.u0, ph.bs, ph.t0
    normal, law, damping, belt, cd = asm.normal, asm.law, asm.damping, asm.belt, asm.contact_dir
    elastic = (asm.spring_k, asm.spring_dir, asm.damper_c, asm.damper_dir)
    forcing = (asm.force_amp, asm.force_omega, asm.force_phi, asm.force_dir)
    for s in range(nsub):
        mid = ta + (s + 0.5) * h
        for g in range(len(nodes)):
            tau = mid + 0.5 * h * nodes[g]
            modal_raw(lam, z0, b0, b1, bh, theta, om, tau, z)
            state_raw(vm, zm, rm, u0, bs, tau, z, q, v)
            c = element_powers(elastic, forcing, q, v, t0 + tau, p)
            slip_forces(normal, law, modes, q, f)
            if len(stuck):
                held_forces(damping, keff, f0, he, stuck, forcing, q, v, t0 + tau, f, rest)
            contact_powers(belt, cd, modes, f, v, c, p)
            for c in range(len(acc)):
                acc[c] += 0.5 * h * weights[g] * p[c]

