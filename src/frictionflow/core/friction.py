"""Friction laws as compiled scalar functions.

A law reaches the kernels as a float64 array ``p`` with this layout:

===========  =====================================================
``p[LAW]``   law code: KARNOPP, COULOMB or STRIBECK
``p[FD]``    kinetic friction F_d
``p[FS]``    maximum static friction F_s
``p[VD]``    stick-band half width V_d (Karnopp's; for the other
             laws the band fixed-step RK4 uses)
``p[RESULTANT]`` 1.0: F_e = X + 2 zeta X'; 0.0: F_e = X
``p[VS]``    Stribeck velocity V_s
``p[DELTA]`` Stribeck exponent delta
``p[VISC]``  viscous friction coefficient (Stribeck)
===========  =====================================================
"""

from __future__ import annotations

import math

from numba import njit

KARNOPP = 0
COULOMB = 1
STRIBECK = 2

LAW, FD, FS, VD, RESULTANT, VS, DELTA, VISC = range(8)
N_PARAMS = 8

#: friction mode codes recorded by the solvers
SLIP_NEG = -1
STICK = 0
SLIP_POS = 1


@njit(cache=True, inline="always")
def slip_magnitude(law, fd, fs, vs, delta, visc, speed):
    """|F| while slipping at relative speed ``speed`` >= 0."""
    if law == STRIBECK:
        return fd + (fs - fd) * math.exp(-((speed / vs) ** delta)) + visc * speed
    return fd


@njit(cache=True, inline="always")
def band_force(law, fd, fs, vd, resultant, vs, delta, visc, x, v, zeta, vb):
    """Friction force of a law with a stick band |V_r| <= V_d (Karnopp's scheme).

    Returns ``(F_c, mode)`` with mode -1/0/+1 for slip-/stick/slip+.
    """
    vr = vb - v
    if vr > vd:
        return slip_magnitude(law, fd, fs, vs, delta, visc, vr), 1
    if vr < -vd:
        return -slip_magnitude(law, fd, fs, vs, delta, visc, -vr), -1
    fe = x + 2.0 * zeta * v if resultant else x
    if fe >= fs:
        return fs, 0
    if fe <= -fs:
        return -fs, 0
    return fe, 0
