"""The steady-state classifier: periodic, equilibrium and still decaying."""

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, Karnopp, RK4, analyze, simulate, steady_state
from frictionflow.core import sections as sec
from frictionflow.quantities import KINDS


def test_periodic_case1(case1_run):
    ss = steady_state(case1_run)
    assert ss.kind == "periodic"
    assert ss.period == pytest.approx(2 * math.pi, rel=1e-8)
    assert ss.n_periods >= 3
    t0, t1 = ss.window
    # a whole number of periods, cut at the first sample after the section
    assert (t1 - t0) / ss.period == pytest.approx(ss.n_periods, abs=1e-3 / ss.period)


def test_decaying_case2_is_a_certified_equilibrium_with_decay_rate_zeta():
    # Case II (zeta > 0, F_s = F_d) spirals in pure slip towards X* = F_d at rate zeta.  It leaves the band at
    # its edge, X' = V_b - V_d, with X ~ X*: on the rim of the disc X'^2 + (X - X*)^2 <= (V_b - V_d)^2 from
    # which it can never reach the band again (core/certificate.py), and inside it once it has decayed a little.
    zeta, vb, vd = 0.01, 0.01, 1e-3
    tr = simulate(BeltOscillator(zeta=zeta, vb=vb), Karnopp(0.02, vd=vd, stick_force="spring"), RK4(dt=1e-3), t_end=600.0)
    ss = steady_state(tr)
    assert ss.kind == "equilibrium" and ss.stability == "stable"
    assert ss.decay_rate == pytest.approx(zeta, rel=1e-12)
    assert ss.limit["x"] == pytest.approx(0.02, abs=1e-12)
    assert 0.0 < ss.window[0] < 4 * math.pi
    assert ss.period is None


def test_equilibrium_once_the_spiral_has_died_out():
    tr = simulate(BeltOscillator(zeta=0.1, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3), t_end=300.0)
    ss = steady_state(tr)
    assert ss.kind == "equilibrium"
    assert ss.limit["x"] == pytest.approx(0.02, abs=1e-12)
    assert analyze(tr).TR_B == pytest.approx(1.0, abs=1e-9)


def _spiral_records(q, n=12, amp=0.01, centre=0.02, jitter=0.0, seed=0):
    """Section records of an oscillation whose amplitude is multiplied by q every period 2 pi."""
    rng = np.random.default_rng(seed)
    rec = np.full((n, sec.NF), np.nan)
    for k in range(n):
        a = amp * q**k
        rec[k, sec.T] = 2 * math.pi * k
        rec[k, sec.X] = centre + a + jitter * rng.standard_normal()
        rec[k, sec.LO] = centre - a * math.sqrt(q) + jitter * rng.standard_normal()
        rec[k, sec.VMIN], rec[k, sec.VMAX] = -a, a
    tail = np.full(sec.NA, np.nan)
    tail[sec.A_XMIN], tail[sec.A_XMAX] = centre - amp * q**n, centre + amp * q**n
    tail[sec.A_VMIN], tail[sec.A_VMAX] = -amp * q**n, amp * q**n
    return rec, tail


@pytest.mark.parametrize("q", [1 - 1e-6, 1 - 1e-9, 1 + 1e-9])
def test_geometric_decay_or_growth_is_never_periodic(q):
    # per period the amplitude changes by 1e-6 (above rtol 1e-8) or 1e-9 (below it, but steadily, far above
    # the solver noise 1e-13 of the scale): neither is a cycle
    rec, tail = _spiral_records(q)
    scale = sec.scale_of(rec, tail, 0.01, 0.02)
    cls = sec.classify(rec, tail, scale, 1e-8, 3, 0.0, False, 1e-13 * scale)
    assert KINDS[int(cls[sec.C_KIND])] == "not_settled"


def test_a_cycle_repeating_to_rounding_is_periodic():
    rec, tail = _spiral_records(1.0, jitter=1e-16)
    tail[sec.A_XMIN], tail[sec.A_XMAX] = 0.01, 0.03
    scale = sec.scale_of(rec, tail, 0.01, 0.02)
    cls = sec.classify(rec, tail, scale, 1e-8, 3, 0.0, False, 1e-13 * scale)
    assert KINDS[int(cls[sec.C_KIND])] == "periodic" and cls[sec.C_PERIOD] == pytest.approx(2 * math.pi)


def test_manual_window_keeps_the_detected_kind(case1_run):
    ss = steady_state(case1_run, window=(50.0, 60.0))
    assert ss.kind == "periodic" and ss.manual_window
    assert ss.window == (50.0, 60.0)
    with pytest.raises(ValueError, match=r"^window must satisfy"):
        steady_state(case1_run, window=(50.0, 500.0))
