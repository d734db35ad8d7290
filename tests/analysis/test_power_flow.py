"""Power flow (Eq. 7-9): balance over a period, independent quadrature, P_belt/P_heat split."""

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Karnopp, RK4, analyze, instantaneous_power, power_flow, simulate


@pytest.fixture(scope="module")
def stick_slip():
    """A damped stick-slip limit cycle (F_s > F_d keeps it alive despite zeta > 0)."""
    tr = simulate(BeltOscillator(zeta=0.05, vb=0.01), Karnopp(0.02, fs=0.04), RK4(dt=1e-3), t_end=150.0)
    return tr, analyze(tr)


def test_stick_slip_orbit_is_periodic_with_sticking(stick_slip):
    tr, res = stick_slip
    assert res.steady_state.kind == "periodic"
    assert 0.05 < res.steady_state.stick_fraction < 0.95


def test_power_balance_closes_over_one_period_undamped(case1_run):
    # Case I is strictly periodic under RK4: over one period P_df = P_fin exactly.
    res = analyze(case1_run)
    t1 = res.steady_state.window[1]
    one = power_flow(case1_run, (t1 - res.steady_state.period, t1))
    assert one.P_df == pytest.approx(one.P_fin, rel=1e-6)
    assert one.energy_residual < 1e-10


def test_power_balance_damped_stick_slip(stick_slip):
    # Fixed-step RK4 through the stick band jitters from cycle to cycle, so
    # K + U differs slightly between the window's ends; the balance
    # P_dv + P_df - P_fin = -Delta(K+U)/tau_p still holds to rounding.
    tr, res = stick_slip
    pf = res.power
    i0, i1 = tr.index(pf.window[0]), tr.index(pf.window[1])
    span = pf.window[1] - pf.window[0]
    d_e = (tr.energy[i1] - tr.energy[i0]) / span
    # RK4 is first order in a step that crosses a switch: each crossing may
    # leave an energy error up to |jump of X''| * |X'| * dt^2 (jump <= 2 F_s).
    switches = np.count_nonzero(np.diff(tr.mode[i0 : i1 + 1]))
    bound = switches * 2 * tr.friction.fs * np.max(np.abs(tr.v)) * 1e-3**2
    assert abs(pf.P_dv + pf.P_df - pf.P_fin + d_e) * span <= bound
    assert pf.energy_residual * pf.P_fin * span <= bound
    # ... and the jitter it leaves is small against the flows themselves
    assert abs(pf.R_c + pf.R_f - 1.0) < 3e-3 * max(1.0, res.steady_state.jitter / 1e-3)
    assert pf.P_dv > 0 and pf.P_df > 0


def test_work_integrals_agree_with_independent_quadrature(stick_slip):
    # The solver integrates the works with its RK4 stages; the trapezoid rule on
    # the samples is an independent estimate (first order at the switches).
    tr, res = stick_slip
    i0, i1 = tr.index(res.steady_state.window[0]), tr.index(res.steady_state.window[1])
    p = instantaneous_power(tr)
    s = slice(i0, i1 + 1)
    span = tr.t[i1] - tr.t[i0]
    trap = lambda y: np.trapezoid(y[s], tr.t[s]) / span  # noqa: E731
    assert res.power.P_dv == pytest.approx(trap(p["P_dv"]), rel=1e-4)
    assert res.power.P_fin == pytest.approx(trap(np.maximum(p["P_f"], 0)), rel=1e-3)
    assert res.power.P_df == pytest.approx(trap(np.maximum(-p["P_f"], 0)), rel=1e-3)
    assert res.power.P_heat == pytest.approx(trap(p["P_heat"]), rel=1e-3)


def test_instantaneous_balance_eq8(stick_slip):
    tr, _ = stick_slip
    p = instantaneous_power(tr)
    lhs = p["K_dot"] + p["P_dv"] + p["U_dot"]
    assert np.allclose(lhs, p["P_f"], atol=1e-15)


def test_friction_power_splits_into_belt_minus_heat(stick_slip):
    tr, res = stick_slip
    pf = res.power
    assert pf.P_f == pytest.approx(pf.P_fin - pf.P_df, abs=1e-15)
    assert pf.P_f == pytest.approx(pf.P_belt - pf.P_heat, abs=1e-12)
    p = instantaneous_power(tr)
    assert np.all(p["P_heat"] >= 0)


def test_heat_is_zero_while_sticking_and_belt_work_is_fc_vb_in_slip(stick_slip):
    tr, _ = stick_slip
    p = instantaneous_power(tr)
    stick = tr.mode == 0
    assert np.all(p["P_heat"][stick] == 0)
    slip = ~stick
    assert np.allclose(p["P_belt"][slip], tr.fc[slip] * tr.vb, rtol=1e-12, atol=1e-18)


def test_equilibrium_has_no_friction_input_and_residual_relative_to_energy():
    tr = simulate(BeltOscillator(zeta=0.5, vb=0.01), Karnopp(0.02), RK4(dt=1e-2), t_end=200.0)
    res = analyze(tr)
    assert res.steady_state.kind == "equilibrium"
    assert res.power.P_fin == 0.0  # below rounding of the running integrals
    assert np.isnan(res.power.R_c) and np.isnan(res.power.R_f)
    assert res.power.P_heat == pytest.approx(0.02 * 0.01, rel=1e-9)
    assert res.energy_residual < 1e-9


def test_averages_stay_accurate_deep_in_a_decay():
    # Case II, zeta = 0.03, at tau ~ 595 the damper power is ~1e-21 while the
    # run has dissipated ~V_b^2/2 = 5e-5 in all: averages are sums of the
    # solver's own step integrals, not differences of running totals.
    tr = simulate(BeltOscillator(zeta=0.03, vb=0.01), Karnopp(0.02, stick_force="spring"), RK4(dt=1e-3), t_end=600.0)
    window = (592.427, 598.713)
    pf = power_flow(tr, window)
    i0, i1 = tr.index(window[0]), tr.index(window[1])
    p = instantaneous_power(tr)
    s = slice(i0, i1 + 1)
    span = tr.t[i1] - tr.t[i0]
    quad_dv = np.trapezoid(p["P_dv"][s], tr.t[s]) / span  # independent: samples' quadrature
    quad_in = np.trapezoid(np.maximum(p["P_f"][s], 0.0), tr.t[s]) / span
    assert 1e-23 < pf.P_dv < 1e-19
    assert pf.P_dv == pytest.approx(quad_dv, rel=1e-5)
    assert pf.P_fin == pytest.approx(quad_in, rel=1e-4)
    assert pf.R_c == pytest.approx(quad_dv / quad_in, rel=1e-4)


# -- windows between samples are exact ------------------------------------------------------------------

def _exact_run():
    return simulate(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04), t_end=100.0)


def test_a_window_inside_the_first_stick_phase_has_its_closed_form():
    """From X = F_d at X' = V_b the mass sticks (|X + 2 zeta V_b| < F_s) with X = F_d + V_b tau, F_c = X + 2 zeta V_b:
    over (0.1, 0.2) P_fin = V_b (F_d + 1.5e-3 + 2 zeta V_b), P_dv = 2 zeta V_b^2 -- no sample lies inside."""
    traj = _exact_run()
    assert not ((traj.t > 0.1) & (traj.t < 0.2)).any()
    pf = power_flow(traj, (0.1, 0.2))
    assert pf.window == (0.1, 0.2)
    assert pf.P_fin == pytest.approx(0.01 * (0.02 + 0.01 * 0.15 + 2 * 0.05 * 0.01), rel=1e-13)
    assert pf.P_dv == pytest.approx(2 * 0.05 * 0.01**2, rel=1e-13)
    assert pf.R_f == 0.0


def test_windows_are_additive_whatever_their_ends():
    """W over (a, c) = W over (a, b) + W over (b, c) for ends between samples: the window is the one asked for."""
    traj = _exact_run()
    a, b, c = 5.0, 7.3, 9.53
    whole, left, right = (power_flow(traj, w) for w in ((a, c), (a, b), (b, c)))
    assert whole.window == (a, c)
    for name in ("P_dv", "P_fin", "P_df", "P_heat"):
        joined = (getattr(left, name) * (b - a) + getattr(right, name) * (c - b)) / (c - a)
        assert getattr(whole, name) == pytest.approx(joined, rel=1e-12, abs=1e-18), name
    assert whole.energy_residual < 1e-9


def test_a_window_on_samples_is_the_solvers_sum():
    traj = _exact_run()
    i0, i1 = 3, len(traj) - 5
    pf = power_flow(traj, (traj.t[i0], traj.t[i1]))
    assert pf.P_fin * (traj.t[i1] - traj.t[i0]) == traj.window_work(i0, i1)[1]


@pytest.mark.parametrize("window", [(-1.0, 5.0), (5.0, 101.0), (8.0, 5.0), (5.0, 5.0), ("a", 3)])
def test_a_window_outside_the_run_is_refused(window):
    with pytest.raises(ValueError, match="window"):
        power_flow(_exact_run(), window)
