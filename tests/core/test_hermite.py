"""The Hermite forms of core.hermite: exact on polynomials of their degree, the same on arrays as on scalars."""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow.core.hermite import hermite, hermite_min, quintic

S = np.linspace(0.0, 1.0, 11)


def test_the_cubic_reproduces_a_cubic_on_a_step():
    h, t0 = 0.3, 1.7
    p = np.polynomial.Polynomial([0.2, -1.0, 0.5, 2.0])
    dp = p.deriv()
    t = t0 + h * S
    got = hermite(p(t0), p(t0 + h), h * dp(t0), h * dp(t0 + h), S)
    assert got == pytest.approx(p(t), rel=1e-14, abs=1e-14)


def test_the_quintic_reproduces_a_quintic_and_its_slope():
    h, t0 = 0.3, 1.7
    p = np.polynomial.Polynomial([0.2, -1.0, 0.5, 2.0, -0.7, 0.3])
    dp, ddp = p.deriv(), p.deriv(2)
    t = t0 + h * S
    x, dx = quintic(p(t0), p(t0 + h), h * dp(t0), h * dp(t0 + h), h * h * ddp(t0), h * h * ddp(t0 + h), S)
    assert x == pytest.approx(p(t), rel=1e-13, abs=1e-14)
    assert dx / h == pytest.approx(dp(t), rel=1e-12, abs=1e-13)


def test_arrays_give_what_scalars_give():
    """The array and the scalar forms are separate compilations of one source: LLVM may contract a
    product and a sum into one fused operation in one and not the other (which one is compiled first,
    inside which caller, decides), so they agree to rounding of the terms, not always bit for bit."""
    rng = np.random.default_rng(1)
    a = rng.normal(size=(6, 50))
    s = rng.uniform(size=50)
    c = hermite(a[0], a[1], a[2], a[3], s)
    q, dq = quintic(a[0], a[1], a[2], a[3], a[4], a[5], s)
    scalar_c = np.array([hermite(a[0, k], a[1, k], a[2, k], a[3, k], s[k]) for k in range(50)])
    scalar_q = np.array([quintic(a[0, k], a[1, k], a[2, k], a[3, k], a[4, k], a[5, k], s[k]) for k in range(50)])
    # a difference in one fused operation changes a term by an ulp of the terms' size, not of the result's
    eps = np.finfo(float).eps
    assert np.all(np.abs(c - scalar_c) <= 8 * eps * np.abs(a[:4]).sum(axis=0))
    assert np.all(np.abs(q - scalar_q[:, 0]) <= 16 * eps * np.abs(a).sum(axis=0))
    assert np.all(np.abs(dq - scalar_q[:, 1]) <= 64 * eps * np.abs(a).sum(axis=0))


def test_the_cubic_minimum_inside_the_step():
    # g(s) = (s - 0.25)(s - 0.75): values 3/16 at both ends, slopes -1 and 1, minimum -1/16 at s = 1/2
    s, val = hermite_min(3 / 16, 3 / 16, -1.0, 1.0)
    assert s == pytest.approx(0.5) and val == pytest.approx(-1 / 16)
    assert hermite_min(0.0, 1.0, 1.0, 1.0)[0] == -1.0  # a line: no interior critical point
