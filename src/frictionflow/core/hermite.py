"""Hermite interpolation on one step: the cubic (with its smallest interior value) and the quintic.

Kernels that locate events between the ends of a step (section crossings,
the closest approach to a switching surface) interpolate the event function
from its values and slopes at both ends; :mod:`frictionflow._continuous`
interpolates recorded runs between their samples with the same forms.  The
forms are compiled for scalars and, called with NumPy arrays (from Python),
evaluate element by element.  Slopes are per unit s (a derivative times the
step h), second derivatives per unit s^2 (times h^2).
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def hermite(p0, p1, m0, m1, s):
    """Cubic Hermite interpolant on [0, 1] with values p0, p1 and slopes m0, m1 (per unit s)."""
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1


@njit(cache=True)
def hermite_min(g0, g1, m0, m1):
    """(s, value) of the Hermite cubic's smallest value at an interior critical point (s = -1: none)."""
    # its derivative is a s^2 + b s + c
    a = 6 * g0 + 3 * m0 - 6 * g1 + 3 * m1
    b = -6 * g0 - 4 * m0 + 6 * g1 - 2 * m1
    c = m0
    best_s = -1.0
    best = math.inf
    r0 = -1.0
    r1 = -1.0
    if abs(a) < 1e-300:
        if b != 0.0:
            r0 = -c / b
    else:
        disc = b * b - 4 * a * c
        if disc >= 0.0:
            q = -0.5 * (b + math.copysign(math.sqrt(disc), b))  # the stable quadratic formula
            r0 = q / a
            if q != 0.0:
                r1 = c / q
    for s in (r0, r1):
        if 0.0 < s < 1.0:
            val = hermite(g0, g1, m0, m1, s)
            if val < best:
                best = val
                best_s = s
    return best_s, best


@njit(cache=True)
def quintic(p0, p1, m0, m1, c0, c1, s):
    """(value, slope per unit s) of the quintic Hermite interpolant on [0, 1].

    Values p, slopes m (per unit s) and second derivatives c (per unit s^2) at both ends.
    """
    s2 = s * s
    s3, s4, s5 = s2 * s, s2 * s2, s2 * s2 * s
    p = ((1 - 10 * s3 + 15 * s4 - 6 * s5) * p0 + (s - 6 * s3 + 8 * s4 - 3 * s5) * m0
         + 0.5 * (s2 - 3 * s3 + 3 * s4 - s5) * c0 + (10 * s3 - 15 * s4 + 6 * s5) * p1
         + (-4 * s3 + 7 * s4 - 3 * s5) * m1 + 0.5 * (s3 - 2 * s4 + s5) * c1)
    dp = ((-30 * s2 + 60 * s3 - 30 * s4) * p0 + (1 - 18 * s2 + 32 * s3 - 15 * s4) * m0
          + 0.5 * (2 * s - 9 * s2 + 12 * s3 - 5 * s4) * c0 + (30 * s2 - 60 * s3 + 30 * s4) * p1
          + (-12 * s2 + 28 * s3 - 15 * s4) * m1 + 0.5 * (3 * s2 - 8 * s3 + 5 * s4) * c1)
    return p, dp
