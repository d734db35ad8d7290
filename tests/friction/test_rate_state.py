"""Rate-and-state friction against closed forms, Rice & Ruina's stability threshold and scipy's Radau.

The equations are written here from the law's definition (theta as the state variable, through
psi = ln(V_0 theta / D_c)), independently of the package's.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.signal import find_peaks

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.cli import main
from frictionflow.core import stiff as engine
from frictionflow.analysis.equilibrium import sliding_equilibrium
from frictionflow.friction import RateState
from frictionflow.orbits.stateful_equilibria import state_hopf_points
from frictionflow.solvers import Stiff

N, MU0, A, B, V0 = 1.0, 0.6, 0.01, 0.015, 0.01
VB = 0.02
STATE_LAWS = ("aging", "slip")


def friction(vr, theta, dc):
    """F = N a asinh(V_r / (2 V_0) exp((mu0 + b ln(V_0 theta / D_c)) / a)) (mu0 / a = 60: exp is a float)."""
    return N * A * np.arcsinh(vr / (2.0 * V0) * np.exp((MU0 + B * np.log(V0 * theta / dc)) / A))


def rhs(zeta, dc, state_law):
    """(X, X', theta)' of the belt oscillator: X'' = -X - 2 zeta X' + F, theta' by the aging or the slip law."""
    def f(t, y):
        x, v, theta = y
        vr = VB - v
        s = abs(vr) * theta / dc
        dtheta = 1.0 - s if state_law == "aging" else -s * np.log(s)
        return np.array([v, -x - 2.0 * zeta * v + friction(vr, theta, dc), dtheta])
    return f


def critical_dc(zeta=0.0):
    """D_c at which steady sliding at V_b changes stability, unregularised (see test_rice_ruina...)."""
    # k_cr = N (b - a) / D_c [1 + V^2 / (N a D_c)] = 1 (k = m = 1) at zeta = 0: a quadratic in D_c
    assert zeta == 0.0
    return 0.5 * (N * (B - A) + np.sqrt((N * (B - A)) ** 2 + 4.0 * (B - A) * VB**2 / A))


def numeric_jacobian(f, y, rel=1e-6):
    """Central differences of ``f`` at ``y``, column by column."""
    jac = np.empty((len(y), len(y)))
    for j in range(len(y)):
        h = rel * max(abs(y[j]), 1e-3)
        e = np.zeros(len(y))
        e[j] = h
        jac[:, j] = (f(0.0, y + e) - f(0.0, y - e)) / (2.0 * h)
    return jac


def steady(dc):
    """Steady sliding: X' = 0, theta = D_c / V_b, X = F = N (mu0 + (a - b) ln(V_b / V_0)) (to e^(-120))."""
    return np.array([N * (MU0 + (A - B) * np.log(VB / V0)), 0.0, dc / VB])


@pytest.mark.parametrize("state_law", STATE_LAWS)
def test_steady_sliding_friction_is_the_closed_form(state_law):
    dc = 0.01
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=dc, vref=V0, state_law=state_law)
    closed = N * (MU0 + (A - B) * np.log(VB / V0))
    # damped well (zeta = 0.5): from X = F at V_0 the mass settles on steady sliding
    traj = simulate(BeltOscillator(zeta=0.5, vb=VB), law, Stiff(rtol=1e-10), t_end=200.0, x0=N * MU0, v0=0.0)
    assert traj.fc[-1] == pytest.approx(closed, rel=1e-10)
    assert traj.x[-1] == pytest.approx(closed, rel=1e-10)
    assert law.theta(traj.internal[0, -1]) == pytest.approx(dc / VB, rel=1e-8)
    assert law.sliding_equilibrium(VB) == pytest.approx(closed, rel=1e-12)
    assert law.slip_magnitude(np.array([0.005, 0.05])) == pytest.approx(
        N * (MU0 + (A - B) * np.log(np.array([0.005, 0.05]) / V0)), rel=1e-12)


@pytest.mark.parametrize("state_law", STATE_LAWS)
def test_rice_ruina_threshold_against_the_eigenvalues_of_the_full_state(state_law):
    # Linearised at steady sliding (u = X - X*, w = X', p = ln theta - ln theta*), unregularised
    # (F = N (mu0 + a ln(V/V_0) + b ln(V_0 theta/D_c)); both state laws give p' = w / D_c - (V/D_c) p):
    #   u' = w,  w' = -u - (2 zeta + N a / V) w + N b p,  p' = w / D_c - (V / D_c) p
    # so s^3 + (g + l) s^2 + (1 + g l - N b / D_c) s + l = 0, g = 2 zeta + N a / V, l = V / D_c.  Routh-Hurwitz:
    # stable iff (g + l)(1 + g l - N b / D_c) > l; with a spring k in place of 1 the threshold is
    # k_cr = (g + l)(N b / D_c - g l) / g = N (b - a) / D_c [1 + V^2 / (N a D_c)] at zeta = 0 (Rice & Ruina).
    # The regularised law differs by a relative e^(-2 mu0 / a) = e^(-120) here: the eigenvalues below of the
    # regularised equations (finite differences) must agree with the unregularised cubic's.
    dc_cr = critical_dc()
    for factor in (0.95, 1.0, 1.05):
        dc = factor * dc_cr
        g, lam = N * A / VB, VB / dc
        cubic = np.sort_complex(np.roots([1.0, g + lam, 1.0 + g * lam - N * B / dc, lam]))
        eig = np.sort_complex(np.linalg.eigvals(numeric_jacobian(rhs(0.0, dc, state_law), steady(dc))))
        assert np.allclose(eig, cubic, atol=1e-7)
        top = eig.real.max()
        if factor == 1.0:
            assert abs(top) < 1e-7
        else:
            assert (top > 1e-4) if factor < 1.0 else (top < -1e-4)  # smaller D_c: k_cr > k, unstable


@pytest.mark.parametrize("state_law", STATE_LAWS)
def test_the_hopf_point_in_dc_is_rice_ruinas_critical_stiffness(state_law):
    # the package's own steady sliding (analysis.equilibrium, the states' Newton and the engine's exact
    # Jacobian) and its Hopf search (orbits), against the closed form above
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=0.02, vref=V0, state_law=state_law)
    model = BeltOscillator(zeta=0.0, vb=VB)
    (found,) = state_hopf_points(model, law, "dc", np.linspace(0.012, 0.03, 7))
    assert found == pytest.approx(critical_dc(), rel=1e-9)
    for factor, sign in ((0.95, 1.0), (1.05, -1.0)):
        dc = factor * critical_dc()
        eq = sliding_equilibrium(model, RateState(normal=N, mu0=MU0, a=A, b=B, dc=dc, vref=V0, state_law=state_law))
        g, lam = N * A / VB, VB / dc
        cubic = np.sort_complex(np.roots([1.0, g + lam, 1.0 + g * lam - N * B / dc, lam]))
        assert np.allclose(np.sort_complex(np.array(eq.eigenvalues)), cubic, atol=1e-9)
        assert sign * max(e.real for e in eq.eigenvalues) > 1e-4


def _peak_rate(traj, x_star, t_from):
    """The growth rate of the oscillation about X*: the slope of ln|X - X*| at its peaks (a least-squares line)."""
    keep = traj.t >= t_from
    t, d = traj.t[keep], np.abs(traj.x[keep] - x_star)
    peaks, _ = find_peaks(d)
    return np.polyfit(t[peaks], np.log(d[peaks]), 1)[0]


@pytest.mark.parametrize("state_law", STATE_LAWS)
@pytest.mark.parametrize("factor", [0.9, 1.1])
def test_simulations_decay_or_grow_about_steady_sliding_at_the_linear_rate(state_law, factor):
    dc = factor * critical_dc()
    g, lam = N * A / VB, VB / dc
    rate = np.roots([1.0, g + lam, 1.0 + g * lam - N * B / dc, lam]).real.max()
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=dc, vref=V0, state_law=state_law)
    x_star = steady(dc)[0]
    traj = simulate(BeltOscillator(zeta=0.0, vb=VB), law, Stiff(rtol=1e-11, atol=1e-13), t_end=300.0,
                    x0=x_star + 1e-6, v0=0.0)
    measured = _peak_rate(traj, x_star, 30.0)  # after the real mode (rate about -1.7) has died out
    assert np.sign(measured) == (1.0 if factor < 1.0 else -1.0)
    assert measured == pytest.approx(rate, rel=0.02)


@pytest.mark.parametrize("state_law", STATE_LAWS)
def test_a_transient_against_scipy_radau(state_law):
    dc, zeta, t_end = 0.01, 0.02, 60.0  # unstable sliding (D_c < critical): the oscillation grows
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=dc, vref=V0, state_law=state_law)
    y0 = steady(dc) + np.array([0.005, 0.0, 0.0])
    traj = simulate(BeltOscillator(zeta=zeta, vb=VB), law, Stiff(rtol=1e-11, atol=1e-13), t_end=t_end,
                    x0=y0[0], v0=0.0)
    ref = solve_ivp(rhs(zeta, dc, state_law), (0.0, t_end), y0, method="Radau", rtol=1e-12,
                    atol=[1e-14, 1e-14, 1e-14 * dc / VB], dense_output=True)
    t = np.linspace(0.0, t_end, 2001)
    x, v = traj(t)
    assert np.max(np.abs(x - ref.sol(t)[0])) < 1e-8
    assert np.max(np.abs(v - ref.sol(t)[1])) < 1e-8
    assert np.max(np.abs(law.theta(traj.internal[0]) / ref.sol(traj.t)[2] - 1.0)) < 1e-7


@pytest.mark.parametrize("state_law", STATE_LAWS)
def test_energy_balance_closes_with_no_storage(state_law):
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=0.01, vref=V0, state_law=state_law)
    traj = simulate(BeltOscillator(zeta=0.01, vb=VB), law, Stiff(rtol=1e-10), t_end=100.0,
                    x0=steady(0.01)[0] + 0.005, v0=0.0)
    assert np.all(traj.stored_energy == 0.0)
    bal = traj.interface_balance()
    assert bal.stored == 0.0
    assert abs(bal.residual) < 1e-9 * abs(bal.belt)
    # the heat is the friction's work on the relative motion, integral F V_r dtau (trapezoids on the steps)
    heat = np.trapezoid(traj.fc * (VB - traj.v), traj.t)
    assert bal.heat == pytest.approx(heat, rel=1e-4)


@pytest.mark.parametrize("state_law", STATE_LAWS)
def test_the_engines_derivatives_are_those_of_the_equations(state_law):
    # the compiled law's F, dF/dV_r, dF/dpsi, psi', dpsi'/dV_r, dpsi'/dpsi against central differences of the
    # equations written here (psi = ln(V_0 theta / D_c): psi' = theta' / theta), on both sides of |x| = 1
    dc = 0.01
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=dc, vref=V0, state_law=state_law)
    q = law.kernel_params()

    def force(vr, psi):
        return friction(vr, dc / V0 * np.exp(psi), dc)

    def rate(vr, psi):
        theta = dc / V0 * np.exp(psi)
        s = abs(vr) * theta / dc
        return ((1.0 - s) if state_law == "aging" else -s * np.log(s)) / theta

    # |x| = |V_r| e^Omega / (2 V_0) from about 0.06 to 1e28: both of the engine's branches
    for vr, psi in [(0.02, -0.7), (-0.003, 0.4), (1e-27, 0.0), (-3e-26, -0.2), (0.5, 1.0), (1e-29, 0.0), (-2e-28, 0.1)]:
        d = np.zeros((1, engine.D_RZ + 1))
        f, df_ds = engine.rate_state(q, vr, np.array([psi]), d)
        hv, hp = 1e-6 * abs(vr), 1e-6
        assert f == pytest.approx(force(vr, psi), rel=1e-12)
        assert df_ds == pytest.approx((force(vr + hv, psi) - force(vr - hv, psi)) / (2 * hv), rel=1e-6)
        assert d[0, engine.D_FZ] == pytest.approx((force(vr, psi + hp) - force(vr, psi - hp)) / (2 * hp), rel=1e-6)
        assert d[0, engine.D_RATE] == pytest.approx(rate(vr, psi), rel=1e-12, abs=1e-12)
        if abs(vr) > 1e-6:  # (at |V_r| ~ 1e-26, the asinh's side, a step in V_r is lost next to 1 / theta)
            assert d[0, engine.D_RS] == pytest.approx((rate(vr + hv, psi) - rate(vr - hv, psi)) / (2 * hv), rel=1e-6)
        assert d[0, engine.D_RZ] == pytest.approx((rate(vr, psi + hp) - rate(vr, psi - hp)) / (2 * hp), rel=1e-6)
        assert d[0, engine.D_EZ] == d[0, engine.D_EZZ] == 0.0  # nothing stored
    # at rest: F = 0 with the slope N a e^Omega / (2 V_0), and theta' = 1 (aging) or 0 (slip)
    d = np.zeros((1, engine.D_RZ + 1))
    f, df_ds = engine.rate_state(q, 0.0, np.array([0.0]), d)
    assert f == 0.0 and df_ds == pytest.approx(N * A * np.exp(MU0 / A) / (2.0 * V0), rel=1e-12)
    assert d[0, engine.D_RATE] == pytest.approx(V0 / dc if state_law == "aging" else 0.0, rel=1e-12)


def test_runs_start_from_steady_sliding_at_the_belt_speed():
    law = RateState(dc=0.02, vref=0.01)
    assert law.theta(law.initial_state(0.04)[0]) == pytest.approx(0.02 / 0.04, rel=1e-14)
    assert law.theta(law.initial_state(-0.04)[0]) == pytest.approx(0.02 / 0.04, rel=1e-14)
    assert law.theta(law.initial_state(0.0)[0]) == pytest.approx(0.02 / 0.01, rel=1e-14)  # at rest: theta = D_c / V_0


@pytest.mark.parametrize("bad, message", [
    (dict(normal=0.0), r"^normal must be finite and in \(0, 1000\], got 0"),
    (dict(a=-0.01), r"^a must be finite and in \(0, 100\], got -0.01"),
    (dict(b=-1.0), r"^b must be finite and in \[0, 100\], got -1"),
    (dict(dc=0.0), r"^dc must be finite and in \(0, 1000\], got 0"),
    (dict(vref=-1.0), r"^vref must be finite and in \(0, 1000\], got -1"),
    (dict(mu0=-0.1), r"^mu0 must be finite and in \[0, 100\], got -0.1"),
    (dict(state_law="fast"), r"^state_law must be one of aging, slip, got 'fast'"),
    (dict(mu0=10.0, a=0.01), r"^a must be >= mu0 / 700"),
])
def test_bad_parameters_are_refused_with_one_line(bad, message, capsys):
    with pytest.raises(ValueError, match=message):
        RateState(**bad)
    args = ["simulate", "--friction", "rate_state", "--t-end", "1"]
    args += [a for k, v in bad.items() for a in (f"--{k.replace('_', '-')}", str(v))]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1


@pytest.mark.parametrize("factor, kind", [(0.9, "periodic"), (1.1, "equilibrium")])
def test_the_default_start_slides_and_settles_on_either_side_of_the_threshold(factor, kind):
    # X'(0) = V_b (the other laws' start) is V_r = 0 exactly, which the contact's stiffness at rest holds to
    # rounding (the spring would be dragged along for ever): the default start slides at the belt's speed
    # instead, off steady sliding by N mu0 - X*, and settles on a cycle (unstable side) or on steady sliding
    dc = factor * critical_dc()
    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=dc, vref=V0)
    assert law.start(VB) == (law.fd, 0.0)
    traj = simulate(BeltOscillator(zeta=0.0, vb=VB), law, t_end=3000.0)
    assert traj.x[0] == law.fd and traj.v[0] == 0.0
    assert np.abs(traj.x - steady(dc)[0]).max() < 0.1  # bounded: about steady sliding, never dragged along
    assert analyze(traj).steady_state.kind == kind


def test_a_run_held_at_v_r_zero_is_refused_not_dragged_along():
    # from X'(0) = V_b exactly the Rosenbrock steps extrapolate the force from V_r = 0 with the stiffness at
    # rest (~1e25) and cannot move V_r off it: X would follow the belt for ever at a "friction" the law never
    # gives (F(V_r) = X needs V_r ~ V_0 e^((X - mu0 N) / a)); the solver says so instead
    from frictionflow.solvers.stiff import ResolutionError

    law = RateState(normal=N, mu0=MU0, a=A, b=B, dc=0.03, vref=V0)
    with pytest.raises(ResolutionError, match=r"V_r = V_b - X' reached the rounding of V_b at tau=0 \(and at \d+ "
                                              r"samples up to tau=200\)"):
        simulate(BeltOscillator(zeta=0.1, vb=VB), law, t_end=200.0, v0=VB)  # held from the start, not at the end


def test_the_summary_names_an_unstable_equilibrium(capsys):
    # at the defaults V_b = V_0, so the default start is steady sliding itself, unstable for D_c = 0.005 (k_c = 3
    # > k = 1): the run stays there, and the table said only "equilibrium"
    assert main(["simulate", "--friction", "rate_state", "--dc", "0.005", "--t-end", "50"]) == 0
    out = capsys.readouterr().out
    assert "steady state: equilibrium" in out and re.search(r"│ stability +│ +unstable │", out)
    assert main(["simulate", "--friction", "rate_state", "--dc", "0.05", "--t-end", "50", "--x0", "0.61"]) == 0
    out = capsys.readouterr().out
    assert "steady state: equilibrium" in out and re.search(r"│ stability +│ +stable │", out)
