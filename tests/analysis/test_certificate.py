"""The equilibrium certificate (core/certificate.py) fires where it must and nowhere else.

Independent checks: the secant condition 2 zeta + (F(V_b) - F(V_b - u))/u > 0 evaluated by brute force in
numpy from the slip curve's formula; the energy E = 1/2 X'^2 + 1/2 (X - X*)^2 along simulated motion;
unstable cycles found by shooting, which no certified disc can contain.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, SlipLaw, Stribeck, analyze, simulate
from frictionflow.core import certificate
from frictionflow.orbits import shoot

STRIBECK = Stribeck(0.02, 0.04, 0.05, delta=1)  # the law of issue 11's example


def _brute_radius(F, zeta, vb, n=200_001):
    """Largest r < V_b with 2 zeta + secant > 0 on [-r, r], on a fine grid (the secant at u = 0 by a difference)."""
    u = np.linspace(-vb, vb, n)
    u = u[u != 0.0]
    margin = 2 * zeta + (F(vb) - F(vb - u)) / u
    bad = np.abs(u[margin <= 0.0])
    return min(vb, bad.min()) if bad.size else vb


def test_issue_example_is_the_stable_equilibrium_with_its_decay_rate():
    zeta, vb = 0.05, 0.12
    res = analyze(simulate(BeltOscillator(zeta, vb), STRIBECK, t_end=600.0))
    ss = res.steady_state
    slope = STRIBECK.slip_slope(vb)
    assert ss.kind == "equilibrium" and ss.stability == "stable"
    assert ss.decay_rate == pytest.approx(zeta + slope / 2, rel=1e-9)  # underdamped: Re(-lambda) = (2 zeta + F')/2
    assert ss.limit["x"] == pytest.approx(STRIBECK.sliding_equilibrium(vb), rel=1e-14)
    assert res.power.P_fin == 0.0


def test_radius_matches_the_secant_condition_by_brute_force():
    F = lambda s: 0.02 + 0.02 * np.exp(-s / 0.05)  # noqa: E731  (the Stribeck law above, delta = 1)
    for zeta, vb in ((0.05, 0.12), (0.03, 0.12), (0.3, 0.016), (0.05, 0.3)):
        r = certificate.radius(STRIBECK, zeta, vb)
        truth = _brute_radius(F, zeta, vb)
        assert truth * (1 - 4 / certificate.N_GRID) <= r <= truth, (zeta, vb, r, truth)


def test_an_unstable_equilibrium_is_never_certified():
    zeta, vb = 0.05, 0.02  # 2 zeta + F'(V_b) < 0
    assert 2 * zeta + STRIBECK.slip_slope(vb) < 0
    assert certificate.radius(STRIBECK, zeta, vb) == 0.0
    x_star = STRIBECK.sliding_equilibrium(vb)
    ss = analyze(simulate(BeltOscillator(zeta, vb), STRIBECK, t_end=300.0, x0=x_star + 1e-9, v0=0.0)).steady_state
    assert ss.kind != "equilibrium"


def test_non_monotone_slope_user_law_certifies_only_where_the_secant_allows():
    # a Stribeck fall with a bump at V_r = 0.2: the slope changes sign twice
    def f(s):
        return 0.02 + 0.02 * math.exp(-s / 0.05) + 0.01 * math.exp(-(((s - 0.2) / 0.02) ** 2))

    law = SlipLaw(f)
    zeta, vb = 0.03, 0.12
    F = np.vectorize(f)
    truth = _brute_radius(F, zeta, vb)
    r = certificate.radius(law, zeta, vb)
    assert 0.0 < r <= truth and r >= truth * (1 - 4 / certificate.N_GRID)
    # from inside the disc: the energy about X* never grows, the motion never sticks, and it is certified
    x_star = f(vb)
    tr = simulate(BeltOscillator(zeta, vb), law, t_end=200.0, x0=x_star + 0.95 * r, v0=0.0)
    energy = 0.5 * tr.v**2 + 0.5 * (tr.x - x_star) ** 2
    assert np.all(np.diff(energy) <= 1e-12 * energy[0]) and not (tr.mode == 0).any()
    ss = analyze(tr).steady_state
    assert ss.kind == "equilibrium" and ss.window[0] == 0.0


def test_no_disc_contains_an_unstable_cycle_and_motion_leaving_it_ends_sticking():
    # bistable: the sliding equilibrium is stable, an unstable slip cycle surrounds it, a stick-slip cycle
    # surrounds that.  Started just outside the unstable cycle, the motion hovers near it for a long time,
    # then grows and sticks: the certificate must not fire on the way.
    zeta, vb = 0.03, 0.12
    model = BeltOscillator(zeta, vb)
    x_star = STRIBECK.sliding_equilibrium(vb)
    cycle = shoot(model, STRIBECK, x_star + 0.105)
    assert cycle.multiplier.real > 1.0 and not cycle.has_stick
    r = certificate.radius(STRIBECK, zeta, vb)
    assert r < cycle.state[0] - x_star  # the disc lies inside the unstable cycle
    early = simulate(model, STRIBECK, t_end=150.0, x0=cycle.state[0] + 1e-6, v0=0.0)
    assert analyze(early).steady_state.kind == "not_settled"
    late = analyze(simulate(model, STRIBECK, t_end=400.0, x0=cycle.state[0] + 1e-6, v0=0.0))
    assert late.steady_state.kind == "periodic" and late.steady_state.stick_fraction > 0.0
    # just inside, it decays: slowly at first (never called periodic), then certified
    slow = analyze(simulate(model, STRIBECK, t_end=300.0, x0=cycle.state[0] - 1e-6, v0=0.0)).steady_state
    assert slow.kind == "not_settled" and slow.decay_rate > 0.0
    fast = analyze(simulate(model, STRIBECK, t_end=300.0, x0=cycle.state[0] - 1e-4, v0=0.0)).steady_state
    assert fast.kind == "equilibrium"


def test_coulomb_and_karnopp_use_the_same_disc():
    from frictionflow import Coulomb, Karnopp

    # constant slip force: every secant is 0, so the disc is the whole slip region (minus Karnopp's band)
    assert certificate.radius(Coulomb(0.02, 0.04), 0.05, 0.01) == pytest.approx(0.01, rel=1e-8)
    assert certificate.radius(Karnopp(0.02, vd=1e-3), 0.05, 0.01) == pytest.approx(0.009, rel=1e-8)
    assert certificate.radius(Coulomb(0.02, 0.04), 0.0, 0.01) == 0.0  # undamped: it circles for ever
