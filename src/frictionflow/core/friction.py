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

    Branches, for one trajectory at a time: they are predicted well and keep
    the untaken side off the chain of dependent operations.
    """
    vr = vb - v
    if vr > vd:
        return slip_magnitude(law, fd, fs, vs, delta, visc, vr)
    if vr < -vd:
        return -slip_magnitude(law, fd, fs, vs, delta, visc, -vr)
    fe = x + 2.0 * zeta * v if resultant else x
    if fe >= fs:
        return fs
    if fe <= -fs:
        return -fs
    return fe


@njit(cache=True, inline="always")
def band_force_select(law, fd, fs, vd, resultant, vs, delta, visc, x, v, zeta, vb):
    """:func:`band_force` computing both sides and selecting one: for loops over many lanes, which it lets vectorise."""
    vr = vb - v
    speed = abs(vr)
    mag = slip_magnitude(law, fd, fs, vs, delta, visc, speed)
    slip = mag if vr > 0.0 else -mag
    fe = x + 2.0 * zeta * v if resultant else x
    hold = min(max(fe, -fs), fs)  # F_s sgn(F_e) once |F_e| >= F_s
    return slip if speed > vd else hold


@njit(cache=True, inline="always")
def band_mode(v, vb, vd):
    """Friction mode -1/0/+1 (slip-/stick/slip+) of a law with a stick band."""
    vr = vb - v
    if vr > vd:
        return 1
    if vr < -vd:
        return -1
    return 0
