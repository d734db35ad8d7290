"""The closed form's integrals against their Taylor series summed in exact rational arithmetic.

tau phi1(z) and tau^2 phi2(z), z = lam tau (phi1 = sum z^j / (j + 1)!, phi2 = sum z^j / (j + 2)!): below
|z| = 1 the engine sums phi2's series by Horner's rule with as many terms as |z| needs
(:func:`frictionflow.core.structure.spectral.phis`), and e^z = 1 + z phi1 from them; here 40 terms in fractions
(the rest below 1e-48).
"""

from __future__ import annotations

import cmath
import math
from fractions import Fraction

import numpy as np
import pytest

from frictionflow.core.structure.spectral import phi2_pair, phis


def exact_series(z: complex, first: int) -> complex:
    """sum_{j < 40} z^j / (j + first)! in fractions (first = 0: e^z) (z's float parts taken exactly), rounded once."""
    zr, zi = Fraction(z.real), Fraction(z.imag)
    tr, ti = Fraction(1, math.factorial(first)), Fraction(0)
    sr, si = tr, ti
    for j in range(1, 40):
        tr, ti = (tr * zr - ti * zi) / (j + first), (tr * zi + ti * zr) / (j + first)
        sr, si = sr + tr, si + ti
    return complex(float(sr), float(si))


def arguments():
    rng = np.random.default_rng(8)
    out = [complex(0.3, 0.0), complex(0.0, 0.95), complex(-0.7, 0.7), complex(1e-9, -2e-9), complex(0.0, 0.0)]
    for _ in range(40):
        r, a = rng.uniform(0.0, 0.999), rng.uniform(-math.pi, math.pi)
        out.append(cmath.rect(r, a))
    return out


@pytest.mark.parametrize("tau", [0.37, 2.0])
def test_phis_below_the_series_limit_match_the_exact_series(tau):
    for z in arguments():
        lam = z / tau
        e, p1, p2 = phis(lam, tau)
        zz = lam * tau  # the argument the engine forms (lam tau may differ from z in the last bit)
        exp, phi1, phi2 = exact_series(zz, 0), exact_series(zz, 1), exact_series(zz, 2)
        assert abs(e - exp) <= 4e-16 * abs(exp)
        assert abs(p2 - tau * tau * phi2) <= 4e-16 * abs(tau * tau * phi2)
        assert abs(p1 - tau * phi1) <= 4e-16 * abs(tau * phi1)


def test_phi2_pair_matches_the_exact_series_at_both_signs():
    """phi2(w) and phi2(-w) from one series in w^2 (the work quadrature's node pairs) against the exact series."""
    for w in arguments():
        plus, minus = phi2_pair(w)
        for got, z in ((plus, w), (minus, -w)):
            exact = exact_series(z, 2)
            assert abs(got - exact) <= 4e-16 * abs(exact)
