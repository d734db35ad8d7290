"""The forced classifier's exponent ends its averaging once it is negative beyond its uncertainty.

Compared with the full 400-period averaging it replaces: on a grid of forced
Coulomb points that have not settled by t_end = 300 the kind and the sign are
the same, and the value is within the uncertainty the stop was judged with
(twice the spread of the running estimate, at least 1e-4).  Chaotic and
quasi-periodic motions never end early: their exponents are those of the full run.
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.analysis.forced import section_indices
from frictionflow.analysis.lyapunov import lyapunov_exponents
from frictionflow.core.strobe import (LYAPUNOV_PERIODS, LYAPUNOV_SPREAD_FLOOR, LYAPUNOV_STEPS, LYAPUNOV_STOP,
                                      LYAPUNOV_TRANSIENT)
from frictionflow.friction import Coulomb
from frictionflow.solvers import Exact

LAW = Coulomb(0.02, 0.04)
# decaying transients near resonance: their stroboscopic sections still drift at tau = 300
GRID = [(omega, zeta) for omega in (0.97, 0.984, 1.0, 1.016, 1.03) for zeta in (0.02, 0.028, 0.036, 0.044)]
FACTOR, FLOOR = LYAPUNOV_STOP[2], LYAPUNOV_STOP[3]


def _exponents(model: BeltOscillator, x0: float, v0: float, stop):
    period = model.forcing_period
    return lyapunov_exponents(model, LAW, x0, v0, t_transient=LYAPUNOV_TRANSIENT * period,
                              t_end=(LYAPUNOV_TRANSIENT + LYAPUNOV_PERIODS) * period, steps_per_block=LYAPUNOV_STEPS,
                              stop=stop)


def _kind(lam: float, spread: float) -> str:
    """The classifier's verdict from the exponent alone (a torus would also need the section to revisit)."""
    spread = max(spread, LYAPUNOV_SPREAD_FLOOR)
    return "chaotic" if lam > spread else ("near_zero" if abs(lam) <= spread else "negative")


def test_early_stop_keeps_kind_sign_and_value_within_its_uncertainty_on_a_grid():
    stopped = 0
    for omega, zeta in GRID:
        model = BeltOscillator(zeta=zeta, vb=0.01, fex=0.05, omega=omega)
        traj = simulate(model, LAW, Exact(), t_end=300.0)
        ss = analyze(traj).steady_state
        assert ss.kind == "not_settled", (omega, zeta)  # the section does not repeat: the exponent decides
        i = section_indices(traj)[-1]
        full = _exponents(model, float(traj.x[i]), float(traj.v[i]), None)
        early = _exponents(model, float(traj.x[i]), float(traj.v[i]), LYAPUNOV_STOP)
        assert full.settings["blocks"] == LYAPUNOV_PERIODS
        lam_full, lam = full.exponents[0], early.exponents[0]
        assert ss.lyapunov == lam  # what analyze reports is the early-stopped value
        assert _kind(lam, early.spread[0]) == _kind(lam_full, full.spread[0]) == "negative", (omega, zeta)
        assert abs(lam - lam_full) <= FACTOR * max(early.spread[0], FLOOR), (omega, zeta, lam, lam_full, early.spread)
        # the stopped run is the full run's beginning, bit for bit
        n = early.settings["blocks"]
        np.testing.assert_array_equal(early.running, full.running[:n])
        stopped += n < LYAPUNOV_PERIODS
    assert stopped == len(GRID)  # (else the comparison above would not test the stop)


@pytest.mark.parametrize("model, law, x0, v0", [
    (BeltOscillator(zeta=0.01, vb=0.1, fex=0.5, omega=1.0), Coulomb(0.5, 1.0), 0.0, 0.0),  # chaotic, lambda_1 ~ 0.08
    (BeltOscillator(zeta=0.05, vb=0.01, fex=0.003, omega=2.1), LAW, 0.02, 0.01),  # a torus, lambda_1 ~ 0
], ids=["chaotic", "torus"])
def test_exponents_that_are_not_clearly_negative_are_averaged_over_every_period(model, law, x0, v0):
    period = model.forcing_period
    runs = [lyapunov_exponents(model, law, x0, v0, t_transient=LYAPUNOV_TRANSIENT * period,
                               t_end=(LYAPUNOV_TRANSIENT + LYAPUNOV_PERIODS) * period, steps_per_block=LYAPUNOV_STEPS,
                               stop=stop) for stop in (None, LYAPUNOV_STOP)]
    assert runs[0].settings["blocks"] == runs[1].settings["blocks"] == LYAPUNOV_PERIODS
    assert runs[0].exponents == runs[1].exponents


@pytest.mark.parametrize("stop", [(1, 20, 2.0, 1e-4), (60, 0, 2.0, 1e-4), (60, 20, 0.0, 1e-4), (60, 20, 2.0, -1.0),
                                  (60, 20, 2.0), "60,20"])
def test_a_bad_stop_rule_is_refused_in_one_line(stop):
    with pytest.raises(ValueError, match=r"^stop must be") as e:
        lyapunov_exponents(BeltOscillator(zeta=0.05, vb=0.01, fex=0.05, omega=1.0), LAW, stop=stop)
    assert "\n" not in str(e.value)
