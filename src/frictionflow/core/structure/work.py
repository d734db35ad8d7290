"""The work of each element over a stretch of a phase: Gauss-Legendre on subintervals, exact to rounding.

Channels, in order: springs, dampers, forces (the work each does on the
structure), then per contact the belt's input F_j b_j and then per contact the
interface heat F_j V_r,j (>= 0).  The power of each is a polynomial in the
phase's exponentials e^{lam tau}, e^{+-i Omega tau} (and tau, at a zero
eigenvalue or a resonance), with exponents of modulus at most
mu = 2 max|lam| + 2 max Omega.  Gauss-Legendre with m nodes on a subinterval
of length h integrates e^{mu s} with the error h^(2m+1) (m!)^4 |mu|^(2m) /
((2m+1) ((2m)!)^3) e^{|mu| h} -- relative to the integral, C_m (mu h)^(2m) e^{mu h}
with C_8 = 1.7e-23, C_16 = 3.2e-55, C_32 = 3.6e-128; subintervals of mu h <= 2, 10
and 30 (m = 8, 16, 32) leave it below 1e-17, so the balance KE + PE = sum of the
works closes to rounding.  Each stretch uses the rule with the fewest nodes in all
(a short stretch the 8-node one, a long one the 32-node one).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..layout import FD, STICK
from .phase import modal_into, state_into

#: mu h per subinterval of each rule: C_m (mu h)^(2m) e^{mu h} <= 1e-17 of the integral
MU_H = 2.0
MU_H16 = 10.0
MU_H32 = 30.0
NODES, WEIGHTS = (a.copy() for a in np.polynomial.legendre.leggauss(8))
NODES16, WEIGHTS16 = (a.copy() for a in np.polynomial.legendre.leggauss(16))
NODES32, WEIGHTS32 = (a.copy() for a in np.polynomial.legendre.leggauss(32))


def n_channels(asm) -> int:
    """How many work channels the structure has."""
    return len(asm.spring_k) + len(asm.damper_c) + len(asm.force_amp) + 2 * len(asm.belt)


@njit(cache=True, inline="always")
def friction_into(asm, cb, q, v, t, f, rest):
    """Each contact's friction force into ``f``: +-F_d N_j slipping, the held force (dampers included) stuck.

    ``rest``: room for C q' + K_eff q - f0 - forces(t), computed once for all the stuck contacts.
    """
    n = len(q)
    for j in range(len(f)):
        if cb.modes[j] != STICK:
            nj = asm.normal[j, 0]
            for i in range(n):
                nj += asm.normal[j, 1 + i] * q[i]
            f[j] = cb.modes[j] * asm.law[j, FD] * nj
    if len(cb.stuck) == 0:
        return
    for i in range(n):
        x = -cb.f0[i]
        for b in range(n):
            x += asm.damping[i, b] * v[b] + cb.keff[i, b] * q[b]
        rest[i] = x
    for g in range(len(asm.force_amp)):
        c = asm.force_amp[g] * math.cos(asm.force_omega[g] * t + asm.force_phi[g])
        for i in range(n):
            rest[i] -= asm.force_dir[g, i] * c
    for s in range(len(cb.stuck)):
        lam = 0.0
        for i in range(n):
            lam += cb.HE[s, i] * rest[i]
        f[cb.stuck[s]] = lam


@njit(cache=True, inline="always")
def element_powers(asm, q, v, t, out, c):
    """The springs', dampers' and forces' powers at (q, q', t) into ``out`` from channel ``c``; the next channel."""
    for s in range(len(asm.spring_k)):
        out[c] = -asm.spring_k[s] * (asm.spring_dir[s] @ q) * (asm.spring_dir[s] @ v)
        c += 1
    for d in range(len(asm.damper_c)):
        w = asm.damper_dir[d] @ v
        out[c] = -asm.damper_c[d] * w * w
        c += 1
    for i in range(len(asm.force_amp)):
        out[c] = asm.force_amp[i] * math.cos(asm.force_omega[i] * t + asm.force_phi[i]) * (asm.force_dir[i] @ v)
        c += 1
    return c


@njit(cache=True, inline="always")
def powers(asm, cb, q, v, t, f, rest, out):
    """The power of every channel at (q, q', t), into ``out`` (``f``, ``rest``: room, see :func:`friction_into`)."""
    c = element_powers(asm, q, v, t, out, 0)
    friction_into(asm, cb, q, v, t, f, rest)
    k = len(asm.belt)
    for j in range(k):
        out[c + j] = f[j] * asm.belt[j]
        out[c + k + j] = 0.0 if cb.modes[j] == STICK else f[j] * (asm.belt[j] - asm.contact_dir[j] @ v)


@njit(cache=True)
def rule(x):
    """(nodes, weights, subintervals) of the Gauss-Legendre rule with the fewest nodes over a stretch of mu h = x."""
    n8, n16, n32 = max(1, math.ceil(x / MU_H)), max(1, math.ceil(x / MU_H16)), max(1, math.ceil(x / MU_H32))
    if 8 * n8 <= 16 * n16 and 8 * n8 <= 32 * n32:
        return NODES, WEIGHTS, n8
    if 16 * n16 <= 32 * n32:
        return NODES16, WEIGHTS16, n16
    return NODES32, WEIGHTS32, n32


@njit(cache=True)
def integrate(asm, cb, ph, om, ta, tb, acc):
    """Add each channel's work over [ta, tb] of the phase (local times) to ``acc``."""
    span = tb - ta
    if span <= 0.0:
        return
    mu = 2.0 * (np.abs(cb.lam).max() if len(cb.lam) else 0.0) + 2.0 * (om.max() if len(om) else 0.0)
    nodes, weights, nsub = rule(span * mu)
    h = span / nsub
    n = len(asm.q0)
    p, f = np.empty(len(acc)), np.empty(len(asm.belt))
    z, q, v, rest = np.empty(len(cb.lam), dtype=np.complex128), np.empty(n), np.empty(n), np.empty(n)
    for s in range(nsub):
        mid = ta + (s + 0.5) * h
        for g in range(len(nodes)):
            tau = mid + 0.5 * h * nodes[g]
            modal_into(cb, ph, om, tau, z)
            state_into(cb, ph, tau, z, q, v)
            powers(asm, cb, q, v, ph.t0 + tau, f, rest, p)
            for c in range(len(acc)):
                acc[c] += 0.5 * h * weights[g] * p[c]
