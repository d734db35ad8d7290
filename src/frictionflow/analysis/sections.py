"""Poincaré sections of a sampled trajectory.

The section is X' = 0: a crossing downwards (X' from + to -) is a maximum of
X, a crossing upwards a minimum.  Every orbit of the planar belt oscillator
around its sliding equilibrium crosses it once each way per period.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Crossings:
    """Section crossings: times and displacements at X' = 0."""

    t: np.ndarray
    x: np.ndarray
    index: np.ndarray  # sample index just before each crossing


def crossings(t: np.ndarray, x: np.ndarray, v: np.ndarray, direction: int) -> Crossings:
    """Crossings of X' = 0 going down (``direction=-1``) or up (``+1``).

    The crossing time interpolates X' linearly between samples; X there comes
    from the cubic Hermite interpolant of (X, X') on the interval, accurate to
    O(h^4) while X' = 0 makes X insensitive to the small error in time.
    """
    if direction < 0:
        i = np.nonzero((v[:-1] > 0.0) & (v[1:] <= 0.0))[0]
    else:
        i = np.nonzero((v[:-1] < 0.0) & (v[1:] >= 0.0))[0]
    if len(i) == 0:
        e = np.empty(0)
        return Crossings(e, e, np.empty(0, dtype=np.int64))
    h = t[i + 1] - t[i]
    s = v[i] / (v[i] - v[i + 1])
    tc = t[i] + s * h
    xc = _hermite(x[i], x[i + 1], v[i] * h, v[i + 1] * h, s)
    return Crossings(tc, xc, i)


def _hermite(p0, p1, m0, m1, s):
    s2 = s * s
    s3 = s2 * s
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1
