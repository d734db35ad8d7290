"""Saltation: how a perturbation crosses a switch, stated once for any state size.

A switch happens where h(y, t, lambda) = 0.  A perturbed trajectory reaches
the surface a little earlier or later, and across the switch the field
jumps from f- to f+, so a perturbation (dy, dlambda) carried up to the
switch leaves it as

    dy+ = dy- + (f+ - f-) w / den,   w = n . dy- + h_lambda dlambda,
    den = n . f- + h_t

(n = grad_y h; Aizerman and Gantmacher 1958, Leine and Nijmeijer 2004).  With
no time or parameter dependence of the surface this is the saltation matrix
S = I + (f+ - f-) n^T / (n . f-).  The denominator is the rate at which the
trajectory crosses the surface; 0 is a grazing touch, where no saltation
exists.

:func:`apply` updates tangent columns in place (variational integrators,
flow-map monodromies with a parameter column); :func:`matrix` builds S.  Both
take arrays of any length n: the single mass has n = 2, a multi-DOF engine
passes its own state and surface normal.  The single mass's three switch
kinds (stick onset, slip onset, slip reversal) have closed forms of this
rule that the tangent integrator applies directly; ``tests/core/test_saltation``
holds them to it.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def crossing_rate(f_before, normal, h_t):
    """n . f- + h_t: how fast the trajectory crosses the surface (0: grazing)."""
    den = 0.0
    for i in range(len(normal)):
        den += normal[i] * f_before[i]
    return den + h_t


@njit(cache=True)
def apply(cols, f_before, f_after, normal, h_t, h_par):
    """Carry the tangent columns ``cols`` (n, m) across a switch, in place; returns False at a grazing touch.

    ``h_par[c]``: the surface's derivative in the parameter column ``c``
    perturbs (0 for a column of state perturbations); ``h_t``: its time
    derivative (0 for a surface fixed in time).
    """
    n, m = cols.shape
    den = crossing_rate(f_before, normal, h_t)
    if den == 0.0:
        return False
    for c in range(m):
        w = 0.0
        for i in range(n):
            w += normal[i] * cols[i, c]
        w += h_par[c]
        for i in range(n):
            cols[i, c] += (f_after[i] - f_before[i]) * w / den
    return True


@njit(cache=True)
def matrix(f_before, f_after, normal, h_t=0.0):
    """The saltation matrix S = I + (f+ - f-) n^T / (n . f- + h_t); NaN everywhere at a grazing touch."""
    n = len(normal)
    S = np.eye(n)
    if not apply(S, f_before, f_after, normal, h_t, np.zeros(n)):
        S[:, :] = np.nan
    return S
