"""The steady-state classifier: periodic, equilibrium and still decaying."""

import math

import pytest

from frictionflow import BeltOscillator, Karnopp, RK4, analyze, simulate, steady_state


def test_periodic_case1(case1_run):
    ss = steady_state(case1_run)
    assert ss.kind == "periodic"
    assert ss.period == pytest.approx(2 * math.pi, rel=1e-8)
    assert ss.n_periods >= 3
    t0, t1 = ss.window
    # a whole number of periods, cut at the first sample after the section
    assert (t1 - t0) / ss.period == pytest.approx(ss.n_periods, abs=1e-3 / ss.period)


def test_decaying_case2_is_not_settled_with_decay_rate_zeta():
    # Case II (zeta > 0, F_s = F_d) spirals in pure slip towards X* = F_d at rate zeta.
    zeta = 0.01
    tr = simulate(BeltOscillator(zeta=zeta, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3), t_end=600.0)
    ss = steady_state(tr)
    assert ss.kind == "not_settled"
    assert ss.decay_rate == pytest.approx(zeta, rel=1e-4)
    assert ss.heading == "equilibrium"
    assert ss.limit["x"] == pytest.approx(0.02, abs=1e-9)
    assert ss.period is None


def test_equilibrium_once_the_spiral_has_died_out():
    tr = simulate(BeltOscillator(zeta=0.1, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3), t_end=300.0)
    ss = steady_state(tr)
    assert ss.kind == "equilibrium"
    assert ss.limit["x"] == pytest.approx(0.02, abs=1e-12)
    assert analyze(tr).TR_B == pytest.approx(1.0, abs=1e-9)


def test_weak_decay_is_not_called_periodic():
    # zeta = 1e-4: maxima shrink by 6e-4 per period -- well above rtol.
    tr = simulate(BeltOscillator(zeta=1e-4, vb=0.01), Karnopp(0.02), RK4(dt=1e-3), t_end=200.0)
    ss = steady_state(tr)
    assert ss.kind == "not_settled"
    assert ss.decay_rate == pytest.approx(1e-4, rel=1e-2)


def test_manual_window_keeps_the_detected_kind(case1_run):
    ss = steady_state(case1_run, window=(50.0, 60.0))
    assert ss.kind == "periodic" and ss.manual_window
    assert ss.window == (50.0, 60.0)
    with pytest.raises(ValueError, match=r"^window must satisfy"):
        steady_state(case1_run, window=(50.0, 500.0))
