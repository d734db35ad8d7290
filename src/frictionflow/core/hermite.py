"""The cubic Hermite interpolant on one step, and its smallest interior value.

Kernels that locate events between the ends of a step (section crossings,
the closest approach to a switching surface) interpolate the event function
from its values and slopes at both ends.
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
