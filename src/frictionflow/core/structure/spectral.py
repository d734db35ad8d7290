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

from numba import njit

#: below this |argument| the series is used (its terms fall as 1/k!)
SERIES = 1.0
N_TERMS = 30


@njit(cache=True)
def phi_series(d, first):
    """sum_{j >= 0} d^j / (j + first)!  (first = 1: phi1, first = 2: phi2)."""
    term = 1.0 + 0.0j
    for j in range(2, first + 1):
        term /= j
    s = term
    for j in range(1, N_TERMS):
        term *= d / (j + first)
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
