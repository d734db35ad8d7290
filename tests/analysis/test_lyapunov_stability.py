"""Lyapunov exponents of an overdamped oscillator: RK4's stable step, derived independently of the kernel."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.analysis.lyapunov import lyapunov_exponents


def _amplification(z: float) -> float:
    """|R(z)| of classical RK4 for y' = lambda y, z = h lambda (the series of exp to 4th order)."""
    return abs(1.0 + z + z**2 / 2.0 + z**3 / 6.0 + z**4 / 24.0)


def _fast_rate(zeta: float) -> float:
    return zeta + math.sqrt(zeta * zeta - 1.0)


@pytest.mark.parametrize("zeta", [5.0, 1000.0])
def test_an_unstable_step_is_refused_with_the_least_stable_one(zeta):
    block = 2.0 * math.pi
    with pytest.raises(ValueError) as info:
        lyapunov_exponents(BeltOscillator(zeta=zeta, vb=0.01), Coulomb(0.02), x0=0.02, v0=0.01,
                           t_transient=10.0, t_end=20.0, steps_per_block=4)
    msg = str(info.value)
    assert "\n" not in msg and "steps_per_block=4" in msg
    need = int(re.search(r"at least (\d+) steps", msg).group(1))
    rate = _fast_rate(zeta)
    # the advised count is the least whose step keeps RK4's amplification of the fast mode within 1
    assert _amplification(-rate * block / need) <= 1.0 + 1e-12
    assert _amplification(-rate * block / (need - 1)) > 1.0


def test_at_a_stable_step_the_exponents_are_the_sliding_eigenvalues():
    """Steady sliding under Coulomb friction is linear: the exponents are the two real eigenvalues.

    The block is short (0.5) so that the fast direction keeps e^((lambda_2 - lambda_1) block) far above
    rounding between two orthonormalisations (over the default 2 pi the run renormalises several times per
    block instead: tests/analysis/test_lyapunov_block.py).
    """
    zeta = 5.0
    r = lyapunov_exponents(BeltOscillator(zeta=zeta, vb=0.01), Coulomb(0.02), x0=0.02, v0=0.0,
                           t_transient=20.0, t_end=80.0, block=0.5, steps_per_block=64)
    eig = np.sort(np.roots([1.0, 2.0 * zeta, 1.0]).real)[::-1]
    assert r.exponents == pytest.approx(tuple(eig), rel=1e-4)
