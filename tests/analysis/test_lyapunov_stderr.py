"""The Lyapunov exponent's standard error (batch means) against the scatter of estimates over disjoint windows.

A QA pass read the running estimate's ``spread`` as an error bar; it is a convergence check.  ``stderr`` is the
statistical one: here it is held to what it claims, the scatter of the exponent measured over six disjoint windows
of one chaotic forced run (each window its own run, its own transient).
"""

from __future__ import annotations

import math

import numpy as np

from frictionflow import BeltOscillator, Coulomb
from frictionflow.analysis.lyapunov import lyapunov_exponents

CHAOTIC = BeltOscillator(zeta=0.01, vb=0.1, fex=0.5, omega=1.0)  # the module's example: lambda_1 ~ 0.08
LAW = Coulomb(0.5, 1.0)
PERIOD = 2 * math.pi


def test_the_standard_error_is_the_scatter_of_disjoint_windows():
    windows = [lyapunov_exponents(CHAOTIC, LAW, t_transient=(160 + 800 * k) * PERIOD,
                                  t_end=(960 + 800 * k) * PERIOD) for k in range(6)]
    lam = np.array([w.exponents[0] for w in windows])
    err = np.array([w.stderr[0] for w in windows])
    scatter = float(np.std(lam, ddof=1))
    assert np.all(lam > 0.05)
    # six windows: the sample deviation itself is uncertain by ~30 %, so a factor 2 either way
    assert 0.5 * scatter < float(np.mean(err)) < 2.0 * scatter


def test_an_exponent_that_is_minus_infinity_has_no_standard_error():
    """Stick onsets collapse the tangent map: lambda_2 = -inf, its standard error NaN (None in JSON)."""
    r = lyapunov_exponents(CHAOTIC, LAW, t_transient=160 * PERIOD, t_end=400 * PERIOD)
    assert r.exponents[1] == -math.inf and math.isnan(r.stderr[1]) and math.isfinite(r.stderr[0])
    assert r.as_dict()["stderr"][1] is None


def test_a_run_too_short_for_ten_batches_gives_none():
    r = lyapunov_exponents(CHAOTIC, LAW, t_transient=10 * PERIOD, t_end=40 * PERIOD)
    assert len(r.running) < 40 and all(math.isnan(e) for e in r.stderr)
