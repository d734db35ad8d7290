"""The integrals a phase's closed form is made of, stable where lambda, mu or their difference is 0.

For a modal coordinate z' = lambda z + beta(tau) the solution is

    z(tau) = e^{lambda tau} z(0) + int_0^tau e^{lambda (tau - s)} beta(s) ds,

and beta is a constant, a linear term and harmonic terms e^{+-i Omega s}:
:func:`expint` is int_0^tau e^{lambda (tau - s)} e^{mu s} ds (mu = 0: the
constant term tau phi1(lambda tau)), :func:`linint` the linear term
tau^2 phi2(lambda tau).  Near a resonance (mu = lambda) or a zero eigenvalue
the quotients are replaced by their Taylor series (|d| < 1: 30 terms leave
less than 1e-30 of the sum), so rigid modes and forcing at a natural
frequency need no special case.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from numba import njit

#: below this |argument| the series is used (its terms fall as 1/k!)
SERIES = 1.0
N_TERMS = 30


#: 1 / (j + 2)!: the coefficients of phi2's series
PHI2_COEF = np.array([1.0 / math.factorial(j + 2) for j in range(N_TERMS)])
#: phi2's series to j < n leaves less than 1e-17 of phi2 (|phi2| > 0.28 below |z| = 1) once |re z| + |im z|
#: <= PHI2_REACH[n - 1]: there (|re| + |im|)^n / (n + 2)! <= 1.4e-18, the rest of the tail at most as much again
PHI2_REACH = np.array([(1.4e-18 * math.factorial(n + 2)) ** (1.0 / n) for n in range(1, N_TERMS + 1)])


@njit(cache=True)
def phis(lam, tau):
    """(e^{lam tau}, int_0^tau e^{lam (tau - s)} ds, int_0^tau e^{lam (tau - s)} s ds): one exponential or one series.

    tau phi1(z) and tau^2 phi2(z), z = lam tau; below |z| = 1 from the series of phi2 (as many terms as
    |z| needs, :data:`PHI2_REACH`, summed by Horner's rule: no divisions), phi1 = 1 + z phi2 and
    e^z = 1 + z phi1: there |e^z| >= 1/e, so the two products and sums add under 2 EPS of e^z (measured 1.8 EPS
    against the exact series, cmath.exp's 1 EPS), and no exponential, sine or cosine is evaluated.
    """
    z = lam * tau
    if z.real * z.real + z.imag * z.imag >= SERIES * SERIES:  # |z| >= SERIES, without hypot (one per call)
        e = cmath.exp(z)
        return e, (e - 1.0) / lam, (e - 1.0 - z) / (lam * lam)
    n = phi2_terms(z)
    p2 = complex(PHI2_COEF[n - 1], 0.0)
    for j in range(n - 2, -1, -1):
        p2 = p2 * z + PHI2_COEF[j]
    p1 = 1.0 + z * p2
    return 1.0 + z * p1, tau * p1, tau * tau * p2


@njit(cache=True, inline="always")
def phi2_terms(z):
    """How many terms of phi2's series |z| < :data:`SERIES` needs (:data:`PHI2_REACH`)."""
    reach = abs(z.real) + abs(z.imag)
    n = 1
    while n < N_TERMS and reach > PHI2_REACH[n - 1]:
        n += 1
    return n


@njit(cache=True, inline="always")
def horner(coef, first, count, u):
    """sum_{i < count} coef[first + 2 i] u^i by Horner's rule (every other coefficient)."""
    p = complex(coef[first + 2 * (count - 1)], 0.0)
    for i in range(count - 2, -1, -1):
        p = p * u + coef[first + 2 * i]
    return p


@njit(cache=True)
def phi2_pair(w):
    """(phi2(w), phi2(-w)) for |w| < :data:`SERIES` from one series: phi2(+-w) = E(w^2) +- w O(w^2), E and O
    phi2's even and odd terms (the terms j < n that :func:`phis` sums for w, so the same truncation)."""
    n = phi2_terms(w)
    u = w * w
    even = horner(PHI2_COEF, 0, (n + 1) // 2, u)
    wodd = w * horner(PHI2_COEF, 1, n // 2, u) if n > 1 else 0.0j
    return even + wodd, even - wodd


@njit(cache=True, inline="always")
def over(z, k):
    """z / k for an integer k > 0, part by part: what complex division by k + 0i gives (its ratio
    term is 0), without the general division's branches and products."""
    return complex(z.real / k, z.imag / k)


@njit(cache=True)
def phi_series(d, first):
    """sum_{j >= 0} d^j / (j + first)!  (first = 1: phi1, first = 2: phi2)."""
    term = 1.0 + 0.0j
    for j in range(2, first + 1):
        term /= j
    s = term
    for j in range(1, N_TERMS):
        term *= over(d, j + first)
        s += term
    return s


@njit(cache=True)
def expint(lam, mu, tau):
    """int_0^tau e^{lam (tau - s)} e^{mu s} ds for complex lam, mu and real tau."""
    d = (mu - lam) * tau
    if abs(d) < SERIES:
        return cmath.exp(lam * tau) * tau * phi_series(d, 1)
    return (cmath.exp(mu * tau) - cmath.exp(lam * tau)) / (mu - lam)


@njit(cache=True)
def linint(lam, tau):
    """int_0^tau e^{lam (tau - s)} s ds = tau^2 phi2(lam tau)."""
    z = lam * tau
    if abs(z) < SERIES:
        return tau * tau * phi_series(z, 2)
    return (cmath.exp(z) - 1.0 - z) / (lam * lam)
