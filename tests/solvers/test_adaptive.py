"""The adaptive Dormand-Prince solver: cross-checks, the Hopf point, no chattering, the step cap."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import (
    Adaptive, BeltOscillator, Coulomb, Exact, RK4, SlipLaw, StepLimitError, Stribeck, SwitchMode, analyze, simulate,
    sliding_equilibrium,
)


def test_adaptive_matches_exact_on_coulomb():
    m, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04)
    ref = analyze(simulate(m, law, Exact(), t_end=200))
    res = analyze(simulate(m, law, Adaptive(), t_end=200))
    assert res.steady_state.kind == ref.steady_state.kind == "periodic"
    assert res.steady_state.period == pytest.approx(ref.steady_state.period, rel=1e-9)
    for k in ("X_max", "X_min", "V_min"):
        assert res.amplitude[k] == pytest.approx(ref.amplitude[k], rel=1e-8)
    assert res.power.P_fin == pytest.approx(ref.power.P_fin, rel=1e-8)
    assert res.power.R_c == pytest.approx(ref.power.R_c, rel=1e-8)


def test_adaptive_and_rk4_agree_on_stribeck():
    m = BeltOscillator(zeta=0.05, vb=0.01)
    law = Stribeck(0.02, 0.04, vs=0.02, rk4_band=1e-5)
    ref = analyze(simulate(m, law, Adaptive(), t_end=300))
    res = analyze(simulate(m, law, RK4(dt=1e-4, record_every=10), t_end=300))
    assert ref.steady_state.kind == res.steady_state.kind == "periodic"
    # RK4's band error in X is about sqrt(2 |X''| V_b dt) (see the Karnopp cross-check)
    tol = math.sqrt(2 * law.fs * m.vb * 1e-4)
    assert res.amplitude["X_max"] == pytest.approx(ref.amplitude["X_max"], abs=tol)
    assert res.steady_state.period == pytest.approx(ref.steady_state.period, rel=tol / ref.amplitude["X_max"])


def test_energy_residual_of_the_adaptive_solver():
    res = analyze(simulate(BeltOscillator(zeta=0.05, vb=0.01), Stribeck(0.02, 0.04, vs=0.02), t_end=200))
    assert res.power.energy_residual < 1e-9


@pytest.mark.parametrize("rel", [0.9, 1.1])
def test_hopf_point_of_the_stribeck_law(rel):
    # Linearised about X* = F(V_b): x'' + (2 zeta + F'(V_b)) x' + x = 0, so a small
    # perturbation decays at rate (2 zeta + F'(V_b)) / 2 and the equilibrium changes
    # stability at 2 zeta + F'(V_b) = 0.
    vb = 0.01
    law = Stribeck(0.02, 0.04, vs=0.02)
    zeta_h = -0.5 * law.slip_slope(vb)
    assert law.hopf_damping(vb) == pytest.approx(zeta_h)
    m = BeltOscillator(zeta=rel * zeta_h, vb=vb)
    eq = sliding_equilibrium(m, law)
    assert eq.stability == ("stable" if rel > 1 else "unstable")
    tr = simulate(m, law, Adaptive(), t_end=60, x0=eq.x + 1e-6, v0=0.0)
    # the measured rate: the envelope of |X - X*| at its maxima
    dev = np.abs(tr.x - eq.x)
    peaks = np.where((dev[1:-1] > dev[:-2]) & (dev[1:-1] >= dev[2:]))[0] + 1
    rate = -np.polyfit(tr.t[peaks], np.log(dev[peaks]), 1)[0]
    assert rate == pytest.approx(eq.damping / 2, rel=1e-3) and (rate > 0) == (rel > 1)
    ss = analyze(tr).steady_state
    if rel > 1:  # decaying from inside the certified disc: the equilibrium, with the linear rate
        assert ss.kind == "equilibrium" and ss.decay_rate == pytest.approx(eq.damping / 2, rel=1e-12)
    else:
        assert ss.kind == "not_settled" and ss.decay_rate == pytest.approx(eq.damping / 2, rel=1e-3)


def test_naive_sign_integration_chatters_where_ours_does_not():
    # Coulomb with F_s = F_d, started far from the belt: it sticks at tau ~ 2.58.
    zeta, vb, fd = 0.05, 0.01, 0.02
    x0, v0, t_end = -0.05, 0.0, 15.0

    class Cap(Exception):
        pass

    calls = {"n": 0, "t": 0.0}

    def sign_rhs(t, y):  # what a user would write with scipy
        calls["n"] += 1
        calls["t"] = max(calls["t"], t)
        if calls["n"] > 100_000:
            raise Cap
        return [y[1], fd * np.sign(vb - y[1]) - y[0] - 2 * zeta * y[1]]

    with pytest.raises(Cap):
        solve_ivp(sign_rhs, (0, t_end), [x0, v0], method="RK45", rtol=1e-8, atol=1e-12)
    tr = simulate(BeltOscillator(zeta=zeta, vb=vb), Coulomb(fd), Adaptive(rtol=1e-8), t_end=t_end, x0=x0, v0=v0)
    stick = tr.events["t"][list(tr.events["mode"]).index(SwitchMode.STICK)]
    # 100,000 evaluations did not carry scipy through the stick phase ...
    assert stick < calls["t"] < stick + 1.0
    # ... which our solver crosses with a few hundred steps
    assert tr.t[-1] == t_end and len(tr) < 2000
    ref = simulate(BeltOscillator(zeta=zeta, vb=vb), Coulomb(fd), Exact(), t_end=t_end, x0=x0, v0=v0)
    assert np.allclose(tr.events["t"], ref.events["t"], rtol=0, atol=1e-8)


def test_step_cap_stops_with_where_and_why():
    with pytest.raises(StepLimitError, match=r"max_steps=50 reached at tau=[0-9.]+ \(X=.*mode"):
        simulate(BeltOscillator(zeta=0.05, vb=0.01), Stribeck(), Adaptive(max_steps=50), t_end=100)


def test_user_slip_law_compiled_equals_the_builtin():
    law = Stribeck(0.02, 0.04, vs=0.02)
    user = SlipLaw(lambda s: 0.02 + 0.02 * math.exp(-((s / 0.02) ** 2)))
    assert user.fs == pytest.approx(0.04) and user.fd == pytest.approx(0.02)
    m = BeltOscillator(zeta=0.05, vb=0.01)
    a = simulate(m, law, Adaptive(), t_end=30)
    b = simulate(m, user, Adaptive(), t_end=30)
    assert np.allclose(a.x, b.x, rtol=0, atol=1e-15) and np.array_equal(a.mode, b.mode)


def test_user_slip_law_numba_cannot_compile_runs_in_python():
    table = {"fd": 0.02, "gap": 0.02}  # a dict lookup: not numba-compilable

    def slip(s):
        return table["fd"] + table["gap"] * math.exp(-((s / 0.02) ** 2))

    m = BeltOscillator(zeta=0.05, vb=0.01)
    a = simulate(m, Stribeck(0.02, 0.04, vs=0.02), Adaptive(), t_end=5)
    b = simulate(m, SlipLaw(slip), Adaptive(), t_end=5)
    assert np.allclose(a.x, b.x, rtol=0, atol=1e-14)


@pytest.mark.parametrize("model", [BeltOscillator(zeta=0.05, vb=0.01),
                                   BeltOscillator(zeta=0.05, vb=0.01, fex=0.005, omega=0.9)], ids=["free", "forced"])
def test_a_break_away_where_the_slip_curve_starts_at_fs_is_one_sample(model):
    """Stribeck's slip curve starts at F_s, so X'' is 0 to rounding where a slip begins; that event is the switch's
    own sample, not a second row at the same time (xarray cannot index a time that repeats)."""
    traj = simulate(model, Stribeck(0.02, 0.04), Adaptive(), t_end=200.0)
    breakaways = np.flatnonzero(traj.switches() & (traj.mode != 0))
    assert len(breakaways) >= 5
    assert np.all(np.diff(traj.t) > 0.0)
    ds = traj.to_xarray()
    assert ds.indexes["tau"].is_unique
    t_mid = 0.5 * (traj.t[breakaways[2]] + traj.t[breakaways[2] + 1])
    assert float(ds.interp(tau=[t_mid])["X"][0]) == pytest.approx(traj.at(t_mid)[0], abs=1e-6)
    # the works across the window are whole: the balance closes at every sample as before
    assert abs(analyze(traj).energy_residual) < 1e-9
