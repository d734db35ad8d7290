"""The work integrals' Gauss-Legendre rules: each rule's stretch limit against its own error, and runs on every rule.

The power of an element is a sum of exponentials e^{mu s} with |mu| <= 2 max|lam| + 2 max Omega
(:mod:`frictionflow.core.structure.work`); a rule is used on stretches of mu h up to its limit.  The error
of the m-node rule there is checked here on e^{mu s} itself (real and imaginary mu), against the exact
integral, and the runs that use the short rules (dense samples) against closed forms.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

import frictionflow as ff
from frictionflow.core.structure import work
from frictionflow.solvers.structure import run_assembly

from .builders import chain

EPS = np.finfo(float).eps
RULES = [(4, work.MU_H4), (6, work.MU_H6), (8, work.MU_H), (16, work.MU_H16), (32, work.MU_H32)]


def gauss_error(m: int, mu: complex) -> float:
    """|m-node Gauss-Legendre - exact| / |exact| for int_0^1 e^{mu s} ds."""
    x, w = np.polynomial.legendre.leggauss(m)
    approx = 0.5 * np.sum(w * np.exp(mu * 0.5 * (x + 1.0)))
    exact = np.expm1(mu) / mu if mu.imag == 0.0 else (np.exp(mu) - 1.0) / mu
    return abs(approx - exact) / abs(exact)


def error_bound(m: int, x: float) -> float:
    """C_m x^(2m) e^x, C_m = (m!)^4 / ((2m + 1) ((2m)!)^3): the rule's error on e^{mu s}, |mu| = x."""
    c = math.factorial(m) ** 4 / ((2 * m + 1) * math.factorial(2 * m) ** 3)
    return c * x ** (2 * m) * math.exp(x)


@pytest.mark.parametrize("m, limit", RULES)
def test_each_rule_within_rounding_at_its_limit(m, limit):
    assert error_bound(m, limit) <= 1e-17
    for mu in (limit, -limit, 1j * limit, limit * (0.6 + 0.8j)):
        # what is left is rounding: the nodes' own (one ulp) moves e^{mu s} by |mu| ulps
        assert gauss_error(m, complex(mu)) <= 4 * EPS * max(1.0, abs(mu))


@pytest.mark.parametrize("m, limit", RULES[:3])
def test_error_formula_seen_beyond_the_limit(m, limit):
    """Beyond the limit the error is measurable and the formula bounds it (it is not rounding that passes)."""
    x = 4.0 * limit
    err = gauss_error(m, complex(x))
    assert 1e-14 < err <= error_bound(m, x)


@njit
def rule_size(x):
    """(nodes, subintervals) of :func:`work.rule` (its node arrays are compiled-in constants: not handed to Python)."""
    nodes, _, sub = work.rule(x)
    return len(nodes), sub


@pytest.mark.parametrize("x, nodes", [(0.05, 4), (work.MU_H4, 4), (0.5, 6), (work.MU_H6, 6), (1.5, 8), (100.0, 32)])
def test_rule_picks_the_fewest_nodes(x, nodes):
    m, sub = rule_size(x)
    assert m == nodes
    # no other rule with its own limit uses fewer nodes in all
    assert m * sub == min(m * max(1, math.ceil(x / lim)) for m, lim in RULES)


@pytest.mark.parametrize("dense_dt", [0.01, 0.2])
def test_dense_samples_balance_and_spring_work(dense_dt):
    """Short stretches (the 4- and 6-node rules): the balance closes to rounding and each spring's work is
    -Delta k (e.q)^2 / 2 between any two samples."""
    asm = chain(3, ff.Coulomb(fd=0.3, fs=0.4), belt=[0.1, 0.15, 0.05], q0=[0.3, 0.0, -0.2], v0=[0.0, 0.1, 0.0])
    mo = run_assembly(asm, 20.0, dense_dt=dense_dt)
    assert mo.energy_residual < 1e-13
    n, ch = mo.n, {c: i for i, c in enumerate(mo.channels)}
    size = np.abs(mo.work[:, -1]).sum()
    for s, (e, k) in enumerate(zip(asm.spring_dir, asm.spring_k)):
        q = mo.state[:n]
        expected = -0.5 * k * ((e @ q) ** 2 - (e @ q[:, :1]) ** 2)
        np.testing.assert_allclose(mo.work[ch[f"spring.{s}"]], expected, rtol=0, atol=1e-13 * size)
