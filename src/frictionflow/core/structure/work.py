"""The work of each element over a stretch of a phase: Gauss-Legendre on subintervals, exact to rounding.

Channels, in order: springs, dampers, forces (the work each does on the
structure), then per contact the belt's input F_j b_j and then per contact the
interface heat F_j V_r,j (>= 0).  The power of each is a polynomial in the
phase's exponentials e^{lam tau}, e^{+-i Omega tau} (and tau, at a zero
eigenvalue or a resonance), with exponents of modulus at most
mu = 2 max|lam| + 2 max Omega.  Gauss-Legendre with 8 nodes on a subinterval
of length h integrates e^{mu s} with the error h^17 (8!)^4 |mu|^16 /
(17 (16!)^3) e^{|mu| h} -- relative to the integral, 2e-23 (mu h)^16 e^{mu h};
subintervals of mu h <= 2 leave it below 1e-17, so the balance
KE + PE = sum of the works closes to rounding.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..layout import FD, STICK
from .phase import modal_into, state_into

#: mu h per subinterval: (mu h)^16 e^{mu h} 2e-23 <= 1e-17 of the integral
MU_H = 2.0
_X, _W = np.polynomial.legendre.leggauss(8)
NODES = _X.copy()
WEIGHTS = _W.copy()


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
def powers(asm, cb, q, v, t, f, rest, out):
    """The power of every channel at (q, q', t), into ``out`` (``f``, ``rest``: room, see :func:`friction_into`)."""
    c = 0
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
    friction_into(asm, cb, q, v, t, f, rest)
    k = len(asm.belt)
    for j in range(k):
        out[c + j] = f[j] * asm.belt[j]
        out[c + k + j] = 0.0 if cb.modes[j] == STICK else f[j] * (asm.belt[j] - asm.contact_dir[j] @ v)


@njit(cache=True)
def integrate(asm, cb, ph, om, ta, tb, acc):
    """Add each channel's work over [ta, tb] of the phase (local times) to ``acc``."""
    span = tb - ta
    if span <= 0.0:
        return
    mu = 2.0 * (np.abs(cb.lam).max() if len(cb.lam) else 0.0) + 2.0 * (om.max() if len(om) else 0.0)
    nsub = max(1, int(math.ceil(span * mu / MU_H)))
    h = span / nsub
    n = len(asm.q0)
    p, f = np.empty(len(acc)), np.empty(len(asm.belt))
    z, q, v, rest = np.empty(len(cb.lam), dtype=np.complex128), np.empty(n), np.empty(n), np.empty(n)
    for s in range(nsub):
        mid = ta + (s + 0.5) * h
        for g in range(len(NODES)):
            tau = mid + 0.5 * h * NODES[g]
            modal_into(cb, ph, om, tau, z)
            state_into(cb, ph, tau, z, q, v)
            powers(asm, cb, q, v, ph.t0 + tau, f, rest, p)
            for c in range(len(acc)):
                acc[c] += 0.5 * h * WEIGHTS[g] * p[c]
