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
def phis(lam, tau):
    """(e^{lam tau}, int_0^tau e^{lam (tau - s)} ds, int_0^tau e^{lam (tau - s)} s ds): one exponential, one series.

    tau phi1(z) and tau^2 phi2(z), z = lam tau; below |z| = 1 from the series of phi2 (stopped once a term
    no longer changes the sum) and phi1 = 1 + z phi2.
    """
    z = lam * tau
    e = cmath.exp(z)
    if abs(z) >= SERIES:
        return e, (e - 1.0) / lam, (e - 1.0 - z) / (lam * lam)
    term = 0.5 + 0.0j
    p2 = term
    for j in range(1, N_TERMS):
        term *= over(z, j + 2)
        p2 += term
        if negligible(term, p2):
            break
    return e, tau * (1.0 + z * p2), tau * tau * p2


@njit(cache=True, inline="always")
def over(z, k):
    """z / k for an integer k > 0, part by part: what complex division by k + 0i gives (its ratio
    term is 0), without the general division's branches and products."""
    return complex(z.real / k, z.imag / k)


@njit(cache=True, inline="always")
def negligible(term, total):
    """abs(term) <= 1e-17 abs(total), the same verdict, with the two moduli (hypot) only where it is close.

    max(|re|, |im|) <= |x| <= |re| + |im|: outside a factor 1.01 of the threshold these bounds decide it
    (the moduli's rounding is a few ulps), and the series is evaluated exactly as with the moduli.
    """
    tr, ti, sr, si = abs(term.real), abs(term.imag), abs(total.real), abs(total.imag)
    if tr + ti <= 0.99e-17 * max(sr, si):
        return True
    if max(tr, ti) > 1.01e-17 * (sr + si):
        return False
    return abs(term) <= 1e-17 * abs(total)


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
