"""The adaptive solver under harmonic forcing: closed forms, energy balance, cross-checks, stick exits, strobes.

Model: X'' + 2 zeta X' + X = F_c(V_r) + F_ex cos(Omega tau + phi).  Every
expected value here is derived independently of the kernel: the linear
forced response, the energy balance, RK4 (already forced), and a hybrid
integration by scipy's solve_ivp with its own event location.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import RK4, Adaptive, BeltOscillator, Coulomb, Cubic, SlipLaw, Stribeck, simulate


def energy(tr, i):
    return 0.5 * (tr.x[i] ** 2 + tr.v[i] ** 2)


def strobe_times(model, t_end):
    """k 2 pi / Omega for k = 0, 1, ... up to t_end, computed as the solvers are asked to."""
    period = 2 * math.pi / model.omega
    return np.arange(int(t_end / period + 1e-9) + 1) * period


# -- the linear forced oscillator ------------------------------------------------------------------

@pytest.mark.parametrize("law", [Coulomb(0.02, 0.04), Stribeck(0.02, 0.04, vs=0.02)], ids=["coulomb", "stribeck"])
@pytest.mark.parametrize("omega", [0.8, 1.5])
def test_forced_slip_has_the_linear_steady_state(law, omega):
    # With V_b = 1 and |X'| <= A Omega ~ 0.25 the mass never sticks: V_r > 0.75, where both
    # laws give F_c = F_d exactly (Stribeck's excess is exp(-(0.75/0.02)^2) = 0).  Then
    # X'' + 2 zeta X' + X = F_d + F_ex cos(Omega tau + phi), whose steady state is
    # X = F_d + A cos(Omega tau + phi - delta), A = F_ex / sqrt((1 - Omega^2)^2 + (2 zeta Omega)^2),
    # delta = atan2(2 zeta Omega, 1 - Omega^2).  At tau_k = 2 pi k / Omega:
    # X - F_d = A cos(phi - delta), X' / Omega = -A sin(phi - delta).
    zeta, fex, phi = 0.1, 0.1, 0.3
    m = BeltOscillator(zeta=zeta, vb=1.0, fex=fex, omega=omega, phi=phi)
    t_end = 400.0  # the transient decays as exp(-zeta tau): 4e-18
    tr = simulate(m, law, Adaptive(), t_end=t_end, x0=law.fd, v0=0.0)
    assert len(tr.events["t"]) == 0 and np.all(tr.mode == 1)
    amp = fex / math.hypot(1 - omega**2, 2 * zeta * omega)
    delta = math.atan2(2 * zeta * omega, 1 - omega**2)
    ks = strobe_times(m, t_end)[-5:]
    i = np.searchsorted(tr.t, ks)
    assert np.array_equal(tr.t[i], ks)
    y, yd = tr.x[i] - law.fd, tr.v[i] / omega
    assert np.hypot(y, yd) == pytest.approx(np.full(5, amp), rel=1e-9)
    lag = np.angle(np.exp(1j * (np.arctan2(-yd, y) - (phi - delta))))  # wrapped to (-pi, pi]
    assert np.abs(lag).max() < 1e-9


# -- the energy balance ----------------------------------------------------------------------------

BALANCE_CASES = {
    "stribeck_stick_slip": (BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.8), Stribeck(0.02, 0.04, vs=0.02)),
    "stribeck_spring_stick": (BeltOscillator(zeta=0.05, vb=0.02, fex=0.03, omega=1.2, phi=1.0),
                              Stribeck(0.02, 0.04, vs=0.02, stick_force="spring")),
    "coulomb_stick_slip": (BeltOscillator(zeta=0.02, vb=0.02, fex=0.01, omega=0.5), Coulomb(0.02, 0.04)),
    "coulomb_vb0_stops": (BeltOscillator(zeta=0.05, vb=0.0, fex=0.06, omega=1.3), Coulomb(0.02, 0.04)),
    "coulomb_vb0_fast": (BeltOscillator(zeta=0.05, vb=0.0, fex=0.08, omega=4.0), Coulomb(0.02, 0.04)),
    "cubic": (BeltOscillator(zeta=0.01, vb=0.05, fex=0.02, omega=1.0), Cubic()),
    "stribeck_negative_belt": (BeltOscillator(zeta=0.05, vb=-0.01, fex=0.02, omega=2.0, phi=-0.5),
                               Stribeck(0.02, 0.04, vs=0.02)),
}


@pytest.mark.parametrize("case", sorted(BALANCE_CASES))
def test_energy_balance_of_forced_runs(case):
    # d/dtau (X'^2/2 + X^2/2) = X' (F_c + f - 2 zeta X'): between any two samples
    # Delta E = W_fin - W_fout + W_ex - W_dv.  Checked at every sample (the running sums)
    # to the solver's tolerance, which also places each increment at its own sample.
    m, law = BALANCE_CASES[case]
    tr = simulate(m, law, Adaptive(), t_end=150.0, x0=0.01, v0=0.0)
    w = tr.dwork
    assert np.all(w[:, 1] >= 0) and np.all(w[:, 2] >= 0)
    gained = np.cumsum(w[:, 1] - w[:, 2] + w[:, 4] - w[:, 0])
    de = 0.5 * (tr.x**2 + tr.v**2) - energy(tr, 0)
    scale = np.abs(w).sum()
    assert np.abs(de - gained).max() < 1e-9 * scale
    assert np.abs(w[:, 4]).sum() > 1e-3 * scale  # the external force did work
    stick = tr.mode[:-1] == 0
    assert np.all(w[1:][stick, 3] == 0.0)  # no heat while sticking
    if law.stick_force == "resultant":
        # while sticking the interface holds F_c = X + 2 zeta V_b - f, within the static bound
        assert np.all(np.abs(tr.fc[tr.mode == 0]) <= law.fs * (1 + 1e-12))
        assert tr.fc[tr.mode == 0] == pytest.approx(
            (tr.x + 2 * m.zeta * m.vb - m.external_force(tr.t))[tr.mode == 0], abs=1e-12)


def test_energy_balance_holds_at_a_looser_tolerance_too():
    m, law = BALANCE_CASES["stribeck_stick_slip"]
    tr = simulate(m, law, Adaptive(rtol=1e-7, atol=1e-10), t_end=150.0, x0=0.01, v0=0.0)
    w = tr.dwork
    resid = energy(tr, -1) - energy(tr, 0) - (w[:, 1] - w[:, 2] + w[:, 4] - w[:, 0]).sum()
    assert abs(resid) < 1e-6 * np.abs(w).sum()


# -- cross-checks ----------------------------------------------------------------------------------

def hybrid_reference(m, law, x0, v0, t_end):
    """The forced friction oscillator integrated by solve_ivp, phase by phase.

    Slip in a fixed direction d (DOP853, terminal event d (V_b - X') = 0);
    stick X' = V_b until |F_e - f| reaches F_s (terminal events on both
    bounds, with a step small against the forcing period so that no crossing
    is stepped over).  At V_r = 0 the mass sticks when |F_e - f| < F_s, and
    slips in the direction of F_e - f otherwise.  Returns the times where a
    phase ends and the state there.
    """
    z, vb, fs = m.zeta, m.vb, law.fs

    def held(t, x):
        return (x + 2 * z * vb if law.stick_force == "resultant" else x) - m.external_force(t)

    def at_rest(t, x):
        g = held(t, x)
        return 0 if abs(g) < fs else (1 if g > 0 else -1)

    t, x, v = 0.0, x0, v0
    mode = at_rest(t, x) if v == vb else (1 if vb > v else -1)
    ts, xs, vs = [t], [x], [v]
    while t < t_end:
        if mode == 0:
            bounds = []
            for sign in (1.0, -1.0):
                def bound(tt, y, sign=sign):
                    return sign * held(tt, y[0]) - fs
                bound.terminal, bound.direction = True, 1.0
                bounds.append(bound)
            sol = solve_ivp(lambda tt, y: [vb], (t, t_end), [x], events=bounds, rtol=1e-13, atol=1e-15,
                            max_step=0.01 * m.forcing_period)
            t, x, v = sol.t[-1], sol.y[0, -1], vb
            mode = 1 if held(t, x) > 0 else -1
        else:
            d = mode

            def rhs(tt, y):
                return [y[1], d * law.slip_magnitude(abs(vb - y[1])) + m.external_force(tt) - y[0] - 2 * z * y[1]]

            def restick(tt, y):
                return d * (vb - y[1])
            restick.terminal, restick.direction = True, -1.0
            sol = solve_ivp(rhs, (t, t_end), [x, v], method="DOP853", events=restick, rtol=1e-13, atol=1e-15)
            t, x, v = sol.t[-1], sol.y[0, -1], sol.y[1, -1]
            if sol.status == 1:
                v = vb
                mode = at_rest(t, x)
        ts.append(t)
        xs.append(x)
        vs.append(v)
    return np.array(ts), np.array(xs), np.array(vs)


@pytest.mark.parametrize("m, law", [
    (BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.8), Stribeck(0.02, 0.04, vs=0.02)),
    (BeltOscillator(zeta=0.05, vb=0.0, fex=0.06, omega=1.3), Coulomb(0.02, 0.04)),
], ids=["stribeck_stick_slip", "coulomb_vb0"])
def test_forced_stick_slip_matches_solve_ivp(m, law):
    t_end = 50.0
    rt, rx, rv = hybrid_reference(m, law, 0.0, 0.0, t_end)
    tr = simulate(m, law, Adaptive(), t_end=t_end, x0=0.0, v0=0.0)
    switches = rt[1:-1]
    assert len(switches) >= 10  # a stick-slip motion
    assert tr.events["t"] == pytest.approx(switches, abs=1e-9)
    x, v = tr.at(rt)
    assert np.abs(x - rx).max() < 1e-9 and np.abs(v - rv).max() < 1e-9


def test_forced_stribeck_stick_slip_matches_rk4():
    # RK4 resolves sticking by a band |V_r| <= V_d: with a small band its error in X is of
    # the order sqrt(2 |X''| V_b dt) (as in the unforced cross-check); compared at the strobes
    m = BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.8)
    law = Stribeck(0.02, 0.04, vs=0.02, rk4_band=1e-6)
    t_end, dt = 60.0, 1e-4
    ref = simulate(m, law, Adaptive(), t_end=t_end, x0=0.0, v0=0.0)
    with pytest.warns(UserWarning):  # the band is narrow for this dt: the tolerance below allows for it
        res = simulate(m, law, RK4(dt=dt, record_every=10), t_end=t_end, x0=0.0, v0=0.0)
    ks = strobe_times(m, t_end)
    i = np.searchsorted(ref.t, ks)
    x, v = res.at(ks)
    tol = math.sqrt(2 * law.fs * m.vb * dt)
    assert np.abs(ref.x[i] - x).max() < tol and np.abs(ref.v[i] - v).max() < tol
    assert np.diff(ref.t)[ref.mode[:-1] == 0].sum() > 0.2 * t_end  # the motion sticks a good part of the time


def test_forced_user_slip_law_equals_the_builtin():
    m = BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.8, phi=0.4)
    a = simulate(m, Stribeck(0.02, 0.04, vs=0.02), Adaptive(), t_end=40, x0=0.0, v0=0.0)
    b = simulate(m, SlipLaw(lambda s: 0.02 + 0.02 * math.exp(-((s / 0.02) ** 2))), Adaptive(), t_end=40, x0=0.0, v0=0.0)
    assert np.array_equal(a.mode, b.mode) and np.allclose(a.x, b.x, rtol=0, atol=1e-14)


def test_forced_interpolant_between_samples():
    # Hermite X'' at the samples includes f: the interpolant agrees with the solver's own
    # dense output (samples every 0.05 of another run) between its steps
    m = BeltOscillator(zeta=0.05, vb=0.01, fex=0.05, omega=1.7)
    law = Stribeck(0.02, 0.04, vs=0.02)
    a = simulate(m, law, Adaptive(), t_end=30, x0=0.0, v0=0.0)
    b = simulate(m, law, Adaptive(dense_dt=0.05), t_end=30, x0=0.0, v0=0.0)
    x, v = a.at(b.t)
    assert np.abs(x - b.x).max() < 1e-8 and np.abs(v - b.v).max() < 1e-7


# -- stick exits -----------------------------------------------------------------------------------

@pytest.mark.parametrize("margin", [1e-6, 1e-10])
@pytest.mark.parametrize("side", [1, -1])
def test_a_short_excursion_beyond_fs_during_stick_is_found(margin, side):
    # V_b = 0, X = 0 held: the interface must hold F_e - f = -f = side F_ex sin(Omega tau)
    # (phi = side pi/2), beyond F_s = F_ex / (1 + margin) only while sin(Omega tau) > 1 / (1 + margin):
    # for 2 sqrt(2 margin) / Omega ~ 3e-6 at margin 1e-10 -- 1e-5 of the forcing period.
    # It first reaches F_s at Omega tau* = asin(1 / (1 + margin)), then slips towards -side.
    law = Coulomb(0.02, 0.04)
    omega = 10.0
    m = BeltOscillator(zeta=0.05, vb=0.0, fex=law.fs * (1 + margin), omega=omega, phi=side * math.pi / 2)
    tr = simulate(m, law, Adaptive(), t_end=2.0, x0=0.0, v0=0.0)
    t_star = math.asin(1 / (1 + margin)) / omega
    assert len(tr.events["t"]) >= 2
    assert tr.events["t"][0] == pytest.approx(t_star, abs=1e-9)
    assert int(tr.events["mode"][0]) == side  # slip +1: V_r > 0, the mass moves backwards
    assert int(tr.events["mode"][1]) == 0  # and sticks again, displaced towards -side
    assert tr.x[np.searchsorted(tr.t, tr.events["t"][1])] * side < 0


def test_forcing_within_the_static_bound_never_unsticks():
    law = Coulomb(0.02, 0.04)
    m = BeltOscillator(zeta=0.05, vb=0.0, fex=law.fs * (1 - 1e-9), omega=10.0, phi=math.pi / 2)
    tr = simulate(m, law, Adaptive(), t_end=20.0, x0=0.0, v0=0.0)
    assert len(tr.events["t"]) == 0 and np.all(tr.mode == 0) and np.all(tr.x == 0.0)
    assert np.all(np.abs(tr.fc) <= law.fs)


def test_forcing_that_touches_fs_holds():
    # F_ex = F_s, V_b = 0, X = 0: the held force -f touches F_s at each peak of f without
    # exceeding it, and the law slips from F(0+) = F_s: slipping cannot start (X'' <= 0 there).
    # The solver must hold on, not slip and re-stick at the same instant for ever.
    law = Cubic(stick_force="spring")
    m = BeltOscillator(zeta=1.5, vb=0.0, fex=law.fs, omega=0.8, phi=-0.9960491607510069)
    tr = simulate(m, law, Adaptive(max_steps=10_000), t_end=50.0, x0=0.0, v0=0.0)
    assert np.abs(tr.x).max() < 1e-15 and np.abs(tr.v).max() < 1e-15


# -- stroboscopic samples --------------------------------------------------------------------------

@pytest.mark.parametrize("m, law, solver, periods", [
    (BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.8), Stribeck(0.02, 0.04, vs=0.02), Adaptive(), 20),
    # a dense grid landing on the strobes: one sample each, not two
    (BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=0.5), Stribeck(0.02, 0.04, vs=0.02),
     Adaptive(dense_dt=math.pi / 4), 10),
    # fast forcing, a run that stops and ends sticking
    (BeltOscillator(zeta=0.05, vb=0.0, fex=0.06, omega=3.0), Coulomb(0.02, 0.04), Adaptive(), 30),
    (BeltOscillator(zeta=0.05, vb=0.0, fex=0.02, omega=1.0), Coulomb(0.02, 0.04), Adaptive(), 5),
])
def test_stroboscopic_samples_at_every_forcing_period(m, law, solver, periods):
    t_end = periods * m.forcing_period
    tr = simulate(m, law, solver, t_end=t_end, x0=0.01, v0=0.0)
    ks = strobe_times(m, t_end)
    assert len(ks) == periods + 1
    on = tr.t[None, :] == ks[:, None]
    assert np.all(on.any(axis=1))
    assert np.all(np.diff(tr.t) >= 0) and tr.t[-1] == pytest.approx(t_end, rel=1e-15)
    # no sample a rounding away from a strobe: another sample due there (the dense grid, the
    # tail's start) is put on it, and then is the same state
    near = np.abs(tr.t[None, :] - ks[:, None]) < 1e-9 * (1 + ks[:, None])
    assert np.array_equal(near, on)
    for row in on:
        assert np.ptp(tr.x[row]) < 1e-12 and np.ptp(tr.v[row]) < 1e-12
