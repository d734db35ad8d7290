"""Steady states of a law with internal state (LuGre): judged on the whole state (X, X', z).

The threshold of steady sliding's stability is derived here from the 3 x 3
linearisation by hand (its characteristic polynomial and the Routh-Hurwitz
condition), the eigenvalues checked against numpy on a Jacobian
differenced from the equations written in the test.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.analysis.equilibrium import sliding_equilibrium
from frictionflow.analysis.forced import state_repeat_multiple
from frictionflow.core import strobe
from frictionflow.friction import Dahl, ElastoPlastic, LuGre

from ..friction.test_lugre import g, lugre_rhs

P = dict(fd=0.3, fs=0.5, vs=0.05, delta=2.0, sigma0=1e4, sigma1=100.0, sigma2=0.0)
VB = 0.1


def _hurwitz_margin(zeta, p=P, vb=VB):
    """c2 c1 - c0 of det(lambda I - J) = lambda^3 + c2 lambda^2 + c1 lambda + c0 at steady sliding (V_r = vb > 0).

    With a = sigma0 vb / g, r_V = vb g'/g (dz'/dV_r), r_z = -a, F_V = sigma1 r_V + sigma2, F_z = sigma0 - sigma1 a and
    J = [[0, 1, 0], [-1, -2 zeta - F_V, F_z], [0, -r_V, -a]]:
    c2 = 2 zeta + F_V + a, c1 = (2 zeta + F_V) a + F_z r_V + 1, c0 = a.  Stable iff all c > 0 and c2 c1 > c0.
    """
    gv = g(p, vb)
    u = vb / p["vs"]
    dg = -(p["fs"] - p["fd"]) * p["delta"] * u ** (p["delta"] - 1.0) / p["vs"] * math.exp(-u ** p["delta"])
    a = p["sigma0"] * vb / gv
    r_v = vb * dg / gv
    f_v = p["sigma1"] * r_v + p["sigma2"]
    f_z = p["sigma0"] - p["sigma1"] * a
    c2, c1, c0 = 2 * zeta + f_v + a, (2 * zeta + f_v) * a + f_z * r_v + 1.0, a
    assert c0 > 0 and c2 > 0
    return c2 * c1 - c0


def _differenced_jacobian(rhs, y, eps=1e-7):
    cols = []
    for j in range(3):
        e = np.zeros(3)
        e[j] = eps * max(1.0, abs(y[j]))
        cols.append((np.array(rhs(0.0, y + e)) - np.array(rhs(0.0, y - e))) / (2 * e[j]))
    return np.array(cols).T


ZETA_C = brentq(_hurwitz_margin, 0.0, 1.0)


@pytest.mark.parametrize("zeta", [0.9 * ZETA_C, 0.999 * ZETA_C, 1.001 * ZETA_C, 1.1 * ZETA_C])
def test_steady_sliding_eigenvalues_and_threshold_on_the_whole_state(zeta):
    model = BeltOscillator(zeta=zeta, vb=VB)
    eq = sliding_equilibrium(model, LuGre(**P))
    z_star = g(P, VB) / P["sigma0"]
    assert eq.internal[0] == pytest.approx(z_star, rel=1e-14)
    assert eq.x == pytest.approx(g(P, VB), rel=1e-14)  # X* = F = sigma0 z* at rest
    y = np.array([eq.x, 0.0, z_star])
    rhs = lugre_rhs(P, zeta, VB)
    assert np.max(np.abs(rhs(0.0, y))) < 1e-12  # a fixed point of the equations written here
    jac = _differenced_jacobian(rhs, y)
    np.testing.assert_allclose(eq.matrix, jac, rtol=1e-6, atol=1e-6)
    want = sorted(np.linalg.eigvals(jac), key=lambda l: (-l.real, -l.imag))
    np.testing.assert_allclose(np.array(eq.eigenvalues), want, rtol=1e-6, atol=1e-9)
    assert eq.stability == ("stable" if _hurwitz_margin(zeta) > 0 else "unstable")
    assert eq.stability == ("stable" if zeta > ZETA_C else "unstable")


def test_stiff_bristles_give_back_the_static_threshold():
    # sigma0 vb / g >> 1: the threshold tends to 2 zeta + F'(V_b) = 0 of the steady-sliding force
    static = -LuGre(**P).slip_slope(VB) / 2.0
    assert ZETA_C == pytest.approx(static, rel=1e-2)


def test_stable_steady_sliding_is_an_equilibrium_with_its_states():
    zeta = 1.3 * ZETA_C
    model = BeltOscillator(zeta=zeta, vb=VB)
    law = LuGre(**P)
    eq = sliding_equilibrium(model, law)
    result = analyze(simulate(model, law, t_end=600.0, x0=eq.x + 1e-4, v0=0.0))
    ss = result.steady_state
    assert ss.kind == "equilibrium" and ss.stability == "stable"
    assert ss.decay_rate == pytest.approx(-max(l.real for l in eq.eigenvalues), rel=1e-12)
    assert ss.limit["x"] == pytest.approx(g(P, VB), rel=1e-6)
    assert ss.limit["z"] == pytest.approx(g(P, VB) / P["sigma0"], rel=1e-6)
    assert result.quantities()["P_belt"] == pytest.approx(g(P, VB) * VB, rel=1e-6)  # all heat


def test_unstable_steady_sliding_grows_into_a_stick_slip_cycle():
    model = BeltOscillator(zeta=0.05, vb=VB)
    law = LuGre(**P)
    eq = sliding_equilibrium(model, law)
    assert eq.stability == "unstable" and max(l.real for l in eq.eigenvalues) > 0
    ss = analyze(simulate(model, law, t_end=400.0, x0=eq.x + 1e-4, v0=0.0)).steady_state
    assert ss.kind == "periodic" and ss.stick_fraction > 0.1


@pytest.fixture(scope="module")
def cycle():
    return simulate(BeltOscillator(zeta=0.02, vb=VB), LuGre(**P), t_end=300.0, x0=0.0, v0=0.0)


def test_a_stick_slip_cycle_repeats_in_the_whole_state_on_the_section(cycle):
    ss = analyze(cycle).steady_state
    assert ss.kind == "periodic" and ss.n_periods >= 3
    v = cycle.v
    down = np.flatnonzero((v[:-1] > 0.0) & (v[1:] <= 0.0)) + 1  # the section X' = 0 is sampled: X' is 0 there
    assert np.all(v[down] == 0.0)
    in_window = down[(cycle.t[down] >= ss.window[0]) & (cycle.t[down] <= ss.window[1])]
    assert len(in_window) == ss.n_periods + 1
    x, z = cycle.x[in_window], P["sigma0"] * cycle.internal[0, in_window]  # z in force units (F_s / internal scale)
    amp = np.ptp(cycle.x[in_window[0]:])
    assert np.ptp(x) <= 1e-5 * amp and np.ptp(z) <= 1e-5 * amp
    np.testing.assert_allclose(np.diff(cycle.t[in_window]), ss.period, rtol=1e-6)


def test_a_cycle_whose_internal_state_drifts_is_not_periodic(cycle):
    # X and X' exactly as the periodic run, the bristles drifting by 1e-4 of their scale per unit time: the
    # state on the section no longer repeats
    drift = 1e-4 * (P["fs"] / P["sigma0"]) * cycle.t
    moved = dataclasses.replace(cycle, internal=cycle.internal + drift)
    assert analyze(moved).steady_state.kind == "not_settled"


def test_a_transient_is_not_settled():
    zeta = 1.3 * ZETA_C
    model = BeltOscillator(zeta=zeta, vb=VB)
    eq = sliding_equilibrium(model, LuGre(**P))
    ss = analyze(simulate(model, LuGre(**P), t_end=40.0, x0=eq.x + 0.005, v0=0.0)).steady_state
    assert ss.kind == "not_settled" and ss.heading == "equilibrium" and ss.decay_rate > 0


def test_the_whole_state_repeat_test_is_the_compiled_one_on_x_and_v():
    rng = np.random.default_rng(3)
    for _ in range(200):
        m0 = int(rng.integers(1, 4))
        base = rng.normal(size=(2, m0))
        n = int(rng.integers(4, 40))
        cols = np.tile(base, n // m0 + 1)[:, :n] + rng.normal(size=(2, n)) * (rng.random(n) < 0.1) * 1e-3
        tol = 1e-4
        assert state_repeat_multiple(cols, tol, 3) == strobe.repeat_multiple(cols[0].copy(), cols[1].copy(), tol, 3, 8)


@pytest.mark.parametrize("law", [Dahl(fd=0.3, sigma0=1e3, alpha=2.0), ElastoPlastic(**P, z_ba=1e-5)])
def test_every_bristle_law_rests_at_states_whose_rates_vanish(law):
    z = law.steady_internal(VB)
    assert abs(law.rate(VB, z)[0]) <= 1e-12 * VB
    assert law.force(VB, z) == pytest.approx(law.slip_force(VB), rel=1e-9)


def test_a_forced_cycle_repeats_in_the_whole_state_on_the_stroboscopic_section():
    model = BeltOscillator(zeta=0.3, vb=VB, fex=0.2, omega=0.7)
    traj = simulate(model, LuGre(**P), t_end=300.0, x0=0.3, v0=0.0)
    ss = analyze(traj).steady_state
    assert ss.kind == "periodic" and ss.forcing_multiple == 1 and ss.n_periods >= 3
    period = 2 * math.pi / model.omega
    k = np.round(traj.t / period)
    strobe_idx = np.flatnonzero((np.abs(traj.t - k * period) <= 1e-9 * period) & (traj.t >= ss.window[0]))
    assert len(strobe_idx) == ss.n_periods + 1  # every k 2 pi / Omega is a sample
    amp = np.ptp(traj.x[strobe_idx[0]:])
    for coordinate in (traj.x, traj.v, P["sigma0"] * traj.internal[0]):
        assert np.ptp(coordinate[strobe_idx]) <= 1e-5 * amp
    drift = 1e-4 * (P["fs"] / P["sigma0"]) * traj.t  # the bristles alone drifting: the section does not repeat
    assert analyze(dataclasses.replace(traj, internal=traj.internal + drift)).steady_state.kind == "not_settled"
