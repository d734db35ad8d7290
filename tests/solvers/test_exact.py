"""The exact event-driven solver: derived closed forms, switch times, energy balance."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb, Exact, Karnopp, RK4, SwitchMode, analyze, simulate


def undamped_stick_slip(fd, fs, vb):
    """Derived: Coulomb, zeta = 0, F_s > F_d, starting anywhere on the cycle.

    Stick moves X from 2F_d - F_s to F_s at speed V_b (time 2(F_s - F_d)/V_b);
    slip is the circle of radius R = sqrt((F_s - F_d)^2 + V_b^2) about (F_d, 0),
    run clockwise from (F_s, V_b) to (2F_d - F_s, V_b): an arc of
    pi + 2 atan(V_b / (F_s - F_d)).
    """
    r = math.hypot(fs - fd, vb)
    t_stick = 2 * (fs - fd) / vb
    t_slip = math.pi + 2 * math.atan2(vb, fs - fd)
    return {"period": t_stick + t_slip, "stick": t_stick, "x_max": fd + r, "x_min": fd - r, "v_min": -r}


@pytest.mark.parametrize("fd, fs, vb", [(0.02, 0.04, 0.01), (0.02, 0.03, 0.05), (0.01, 0.05, 0.002)])
def test_undamped_stick_slip_cycle_matches_closed_form(fd, fs, vb):
    want = undamped_stick_slip(fd, fs, vb)
    res = analyze(simulate(BeltOscillator(zeta=0.0, vb=vb), Coulomb(fd, fs), t_end=30 * want["period"]))
    ss = res.steady_state
    assert ss.kind == "periodic"
    assert ss.period == pytest.approx(want["period"], rel=1e-12)
    assert ss.stick_fraction == pytest.approx(want["stick"] / want["period"], rel=1e-10)
    assert res.amplitude["X_max"] == pytest.approx(want["x_max"], rel=1e-12)
    assert res.amplitude["X_min"] == pytest.approx(want["x_min"], abs=1e-14)
    assert res.amplitude["V_min"] == pytest.approx(want["v_min"], rel=1e-12)
    assert res.amplitude["V_max"] == pytest.approx(vb, rel=1e-14)


def test_periodic_coulomb_heat_is_fd_vb():
    # Derived: over a period of a Coulomb orbit, int F_c V_r over slip = F_d (V_b T_slip - dX_slip),
    # and dX_slip = -V_b T_stick, so P_heat = F_d V_b exactly, whatever zeta.
    for zeta in (0.0, 0.05, 0.1):
        res = analyze(simulate(BeltOscillator(zeta=zeta, vb=0.01), Coulomb(0.02, 0.04), t_end=300))
        assert res.steady_state.kind == "periodic"
        assert res.power.P_heat == pytest.approx(0.02 * 0.01, rel=1e-11)


def test_energy_balance_closes_to_rounding():
    for law in (Coulomb(0.02, 0.04), Karnopp(0.02, 0.04), Karnopp(0.02, stick_force="spring"), Coulomb(0.03)):
        for zeta in (0.0, 0.05, 0.7, 1.0, 1.8):
            tr = simulate(BeltOscillator(zeta=zeta, vb=0.01), law, Exact(dense_dt=0.37), t_end=200)
            res = analyze(tr, window=(3.0, 190.0))
            assert res.power.energy_residual <= 1e-10, (law, zeta)


def test_switch_times_agree_with_root_finding_on_the_closed_form():
    # Coulomb, zeta = 0.05, from stick onset: derive the slip arc independently and
    # find where X' returns to V_b with brentq.
    zeta, fd, fs, vb = 0.05, 0.02, 0.04, 0.01
    tr = simulate(BeltOscillator(zeta=zeta, vb=vb), Coulomb(fd, fs), t_end=60)
    ev = tr.events["t"]
    # stick (X' = V_b) ends when X + 2 zeta V_b = F_s; slip starts from (F_s - 2 zeta V_b, V_b)
    w = math.sqrt(1 - zeta**2)
    y0, v0 = fs - 2 * zeta * vb - fd, vb

    def v(t):
        b = (v0 + zeta * y0) / w
        return math.exp(-zeta * t) * ((w * b - zeta * y0) * math.cos(w * t) - (w * y0 + zeta * b) * math.sin(w * t))

    grid = np.linspace(1e-3, 4 * math.pi, 4001)
    g = np.array([v(t) - vb for t in grid])
    k = np.nonzero((g[:-1] < 0) & (g[1:] >= 0))[0][0]  # first return to V_b from below
    t_slip = brentq(lambda t: v(t) - vb, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15)
    # events alternate stick -> slip -> stick; compare every slip duration after the first stick
    modes = tr.events["mode"]
    starts = [i for i in range(len(ev) - 1) if modes[i] == SwitchMode.SLIP_POSITIVE and modes[i + 1] == SwitchMode.STICK]
    assert len(starts) > 3
    for i in starts[1:]:
        assert ev[i + 1] - ev[i] == pytest.approx(t_slip, abs=1e-12)


def test_case1_transient_switch_times_are_the_derived_ones():
    # Karnopp, zeta = 0, F_s = F_d, X(0) = F_d, X'(0) = V_b: leaves the band at
    # arccos(1 - V_d/V_b), re-enters at 2 pi - arccos(1 - V_d/V_b), leaves again after
    # sqrt(V_b^2 - (V_b - V_d)^2) / (V_b - V_d) at constant speed.
    fd, vb, vd = 0.02, 0.01, 1e-3
    tr = simulate(BeltOscillator(zeta=0.0, vb=vb), Karnopp(fd, vd=vd, stick_force="spring"), t_end=40)
    r = vb - vd
    a = math.acos(1 - vd / vb)
    want = [a, 2 * math.pi - a, 2 * math.pi - a + math.sqrt(vb**2 - r**2) / r]
    assert np.allclose(tr.events["t"][:3], want, rtol=0, atol=1e-13)
    assert len(tr.events["t"]) == 3  # then the circle of radius V_b - V_d grazes the band for ever


def test_exact_and_rk4_agree_within_rk4s_band_resolution():
    # Fixed-step RK4 leaves a Karnopp band with an error of about sqrt(2 |X''| V_b dt)
    # in X (see the steady-state docs); the exact solver has none.
    m, law = BeltOscillator(zeta=0.05, vb=0.01), Karnopp(0.02, 0.04)
    ref = analyze(simulate(m, law, Exact(), t_end=300))
    errs = []
    for dt in (1e-3, 2.5e-4):
        res = analyze(simulate(m, law, RK4(dt=dt, record_every=10), t_end=300))
        assert res.steady_state.kind == "periodic"
        err = abs(res.amplitude["X_max"] - ref.amplitude["X_max"])
        assert err <= math.sqrt(2 * law.fs * m.vb * dt)
        errs.append(err)
    assert errs[1] < errs[0]


def test_filippov_sliding_on_the_band_edge_is_what_rk4_chatters_around():
    # Karnopp with F_e = X and zeta > 0: inside the band X'' = -2 zeta X' pushes the
    # mass out, slip pushes it back: it slides on X' = V_b - V_d until F_d - X - 2 zeta X' = 0.
    m, law = BeltOscillator(zeta=0.05, vb=0.01), Karnopp(0.02, 0.04, stick_force="spring")
    tr = simulate(m, law, Exact(), t_end=20)
    assert SwitchMode.BAND_EDGE_LOWER in tr.events["mode"]
    i = list(tr.events["mode"]).index(SwitchMode.BAND_EDGE_LOWER)
    t0, t1 = tr.events["t"][i], tr.events["t"][i + 1]
    x1 = law.fd - 2 * m.zeta * (m.vb - law.vd)
    j = np.searchsorted(tr.t, t1)
    assert tr.x[j] == pytest.approx(x1, rel=1e-12)
    rk = simulate(m, law, RK4(dt=1e-4), t_end=20)
    k0, k1 = rk.index(t0 + 0.1 * (t1 - t0)), rk.index(t0 + 0.9 * (t1 - t0))
    assert np.mean(rk.v[k0:k1]) == pytest.approx(m.vb - law.vd, abs=2e-6)


def test_terminal_slip_is_an_equilibrium_however_short_the_run():
    tr = simulate(BeltOscillator(zeta=0.01, vb=0.01), Karnopp(0.02, stick_force="spring"), t_end=20)
    res = analyze(tr)
    assert res.steady_state.kind == "equilibrium" and res.steady_state.stability == "stable"
    assert res.steady_state.limit["x"] == 0.02
    assert res.steady_state.decay_rate == pytest.approx(0.01)
    assert res.TR_B == 1.0 and res.power.P_heat == pytest.approx(0.02 * 0.01)


def test_overdamped_and_critical_runs():
    for zeta in (1.0, 3.0):
        res = analyze(simulate(BeltOscillator(zeta=zeta, vb=0.01), Coulomb(0.02, 0.04), t_end=50))
        assert res.steady_state.kind == "equilibrium" and res.steady_state.limit["x"] == 0.02
