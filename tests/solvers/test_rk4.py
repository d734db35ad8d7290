"""Fixed-step RK4: order of convergence, the exact zeta = 0 orbit, step warnings."""

import math
import warnings

import numpy as np
import pytest

from frictionflow import BeltOscillator, CoarseStepWarning, Coulomb, Karnopp, RK4, analyze, simulate
from frictionflow.solvers.rk4 import ThinnedOutputWarning
from frictionflow.solvers import rk4 as rk4_module

from ..conftest import slip_solution


def test_fourth_order_convergence_in_pure_slip():
    # V_b = 1 keeps V_r > V_d throughout: the RHS is smooth, RK4 must show order 4.
    zeta, fd, x0, v0, t_end = 0.05, 0.02, 0.1, 0.05, 20.0
    exact_x, exact_v = slip_solution(t_end, x0, v0, fd, zeta)
    errors = []
    dts = [0.2, 0.1, 0.05, 0.025]
    for dt in dts:
        tr = simulate(BeltOscillator(zeta=zeta, vb=1.0), Karnopp(fd), RK4(dt=dt), t_end=t_end, x0=x0, v0=v0)
        assert np.all(tr.mode == 1)
        errors.append(math.hypot(tr.x[-1] - exact_x, tr.v[-1] - exact_v))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 4.0) < 0.15), orders


def test_whole_trajectory_matches_closed_form_in_pure_slip():
    zeta, fd = 0.02, 0.03
    tr = simulate(BeltOscillator(zeta=zeta, vb=1.0), Karnopp(fd), RK4(dt=1e-2), t_end=30.0, x0=0.2, v0=0.0)
    x, v = slip_solution(tr.t, 0.2, 0.0, fd, zeta)
    # RK4 on X'' = -X: e^{ih} - G(ih) = i h^5/120 + O(h^6), a phase error of
    # h^5/120 per step, t h^4 / 120 after time t, times the amplitude 0.2.
    bound = 0.2 * 30.0 * 1e-2**4 / 120
    assert np.max(np.abs(tr.x - x)) < bound
    assert np.max(np.abs(tr.v - v)) < bound


def exact_case1(fd, vb, vd):
    """Derived zeta = 0 orbit from X(0) = F_d, X'(0) = V_b with Karnopp and F_s = F_d.

    The first slip arc is the circle of radius V_b about (F_d, 0).  It meets the
    band X' = V_b - V_d at X = F_d - sqrt(V_b^2 - (V_b - V_d)^2), after an arc of
    2 pi - arccos(1 - V_d / V_b).  In the band F_c = X < F_d and X'' = 0, so the
    mass moves at V_b - V_d until X = F_d, where it leaves on the circle of
    radius R = V_b - V_d, which it keeps for ever (period 2 pi).
    """
    r = vb - vd
    t_entry = 2 * math.pi - math.acos(1 - vd / vb)
    t_band = math.sqrt(vb**2 - r**2) / r
    t_exit = t_entry + t_band
    return r, t_exit


@pytest.mark.parametrize("fd, vb", [(0.02, 0.01), (0.04, 0.01), (0.02, 0.1)])
def test_rk4_converges_to_the_exact_undamped_orbit(fd, vb):
    vd = 1e-3
    r, t_exit = exact_case1(fd, vb, vd)
    tr = simulate(BeltOscillator(zeta=0.0, vb=vb), Karnopp(fd, stick_force="spring", vd=vd), RK4(dt=1e-3), t_end=60.0)
    res = analyze(tr)
    assert res.steady_state.kind == "periodic"
    assert res.steady_state.period == pytest.approx(2 * math.pi, rel=1e-8)
    # The only O(dt) error is where the orbit enters the band; it sets R to
    # about V_b - V_d + |X''| dt with |X''| <= sqrt(2 V_b V_d) there.
    tol = 2 * math.sqrt(2 * vb * vd) * 1e-3
    amp = res.amplitude
    assert amp["X_max"] == pytest.approx(fd + r, abs=tol)
    assert amp["X_min"] == pytest.approx(fd - r, abs=tol)
    assert amp["V_max"] == pytest.approx(r, abs=tol)
    assert amp["V_min"] == pytest.approx(-r, abs=tol)
    # Maxima of X a quarter period after leaving the band, every 2 pi.
    i = np.nonzero((tr.v[:-1] > 0) & (tr.v[1:] <= 0))[0]
    t_max = tr.t[i[1:4]]
    want = t_exit + math.pi / 2 + 2 * math.pi * np.arange(3)
    assert np.max(np.abs(t_max - want)) < 5e-3


def test_undamped_orbit_power_flow_is_the_derived_one(case1_run):
    fd, vb, vd = 0.02, 0.01, 1e-3
    r, _ = exact_case1(fd, vb, vd)
    res = analyze(case1_run)
    pf = res.power
    # On the circle P_f = F_d X' with X' = R cos: positive part averages F_d R / pi.
    assert pf.P_fin == pytest.approx(fd * r / math.pi, rel=1e-5)
    assert pf.P_df == pytest.approx(fd * r / math.pi, rel=1e-5)
    assert pf.P_dv == 0.0
    assert pf.R_f == pytest.approx(1.0, rel=1e-5)
    # Pure slip with F_c = F_d: the belt delivers F_d V_b, all of it heat.
    assert pf.P_belt == pytest.approx(fd * vb, rel=1e-5)
    assert pf.P_heat == pytest.approx(fd * vb, rel=1e-5)
    assert res.TR_B == pytest.approx((fd + r) / fd, rel=1e-5)
    assert pf.energy_residual < 1e-10


def test_record_every_keeps_every_kth_step_and_both_steps_around_each_event(case1_run):
    thin = simulate(BeltOscillator(zeta=0.0, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3, record_every=7), t_end=200.0)
    idx = np.rint(thin.t / 1e-3).astype(int)
    assert set(range(0, 200_001, 7)) <= set(idx.tolist()) and idx[-1] == 200_000
    assert np.array_equal(thin.x, case1_run.x[idx]) and np.array_equal(thin.v, case1_run.v[idx])  # the same steps
    assert len(thin) < 0.2 * len(case1_run)
    # the same step integrals, summed in groups instead of one by one
    assert np.allclose(thin.window_work(0, len(thin) - 1), case1_run.window_work(0, len(case1_run) - 1), rtol=1e-13, atol=0)


@pytest.mark.parametrize("every", [13, 500])
def test_thinned_output_classifies_and_averages_as_every_step(every):
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04)
    full = analyze(simulate(model, law, RK4(dt=1e-3), t_end=200.0)).to_dict()
    thin = analyze(simulate(model, law, RK4(dt=1e-3, record_every=every), t_end=200.0)).to_dict()
    assert thin["steady_state"]["kind"] == full["steady_state"]["kind"] == "periodic"
    assert thin["steady_state"]["window"] == full["steady_state"]["window"]
    assert thin["steady_state"]["period"] == pytest.approx(full["steady_state"]["period"], rel=1e-13)
    assert thin["amplitude"] == full["amplitude"] and thin["TR_B"] == full["TR_B"]
    for key, value in full["averages"].items():
        assert thin["averages"][key] == pytest.approx(value, rel=1e-11), key


def test_automatic_thinning_is_announced(monkeypatch):
    monkeypatch.setattr(rk4_module, "MAX_AUTO_SAMPLES", 1000)
    with pytest.warns(ThinnedOutputWarning, match="keeping one step in 2 "):
        simulate(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04), RK4(dt=1e-3), t_end=2.0)


def test_chunked_run_equals_one_call(monkeypatch, case1_run):
    monkeypatch.setattr(rk4_module, "CHUNK", 12_345)
    tr = simulate(BeltOscillator(zeta=0.0, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3), t_end=200.0)
    assert np.array_equal(tr.x, case1_run.x) and np.array_equal(tr.work, case1_run.work)


def test_coarse_step_warns_with_the_step_that_resolves_it():
    model, law = BeltOscillator(zeta=0.0, vb=0.1), Karnopp(0.02)
    with pytest.warns(CoarseStepWarning, match=r"use dt <= 0\.00[0-9]+"):
        simulate(model, law, RK4(dt=0.05), t_end=1.0)
    with pytest.warns(CoarseStepWarning, match=r"stability limit.*use dt <= 0\.14"):
        simulate(BeltOscillator(zeta=10.0, vb=0.1), Karnopp(0.02, vd=1.0), RK4(dt=0.2), t_end=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate(model, law, RK4(dt=1e-3), t_end=1.0)


def test_the_warned_step_resolves_the_band():
    model, law = BeltOscillator(zeta=0.0, vb=0.1), Karnopp(0.02)
    lim = RK4(dt=1.0).step_limits(model, law, 0.02, 0.1)["band"]
    tr = simulate(model, law, RK4(dt=lim), t_end=50.0)
    # no step changes X' by more than the band width 2 V_d
    assert np.max(np.abs(np.diff(tr.v))) <= 2 * law.vd


@pytest.mark.parametrize("bad, name", [(0.0, "dt"), (-1e-3, "dt"), (float("nan"), "dt")])
def test_bad_step(bad, name):
    with pytest.raises(ValueError, match=rf"^{name} must be finite and in \[1e-09, 1000\]"):
        RK4(dt=bad)


def test_bad_t_end():
    with pytest.raises(ValueError, match=r"^t_end must be finite and in \(0, "):
        simulate(BeltOscillator(), Karnopp(), RK4(), t_end=0.0)
