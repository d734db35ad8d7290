"""Newton shooting on the Poincare map: orbits against long simulations and closed forms."""

from __future__ import annotations

import json
import math

import pytest

from frictionflow import (
    Adaptive,
    BeltOscillator,
    Coulomb,
    Karnopp,
    Stribeck,
    analyze,
    simulate,
)
from frictionflow.orbits import ShootingError, find_orbit, shoot

FD, FS, VB = 0.02, 0.04, 0.01
STRIBECK = Stribeck(FD, FS, 0.01)

ATTRACTORS = [
    ("coulomb stick-slip", BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS), None, 300.0, 1e-10),
    ("karnopp stick-slip", BeltOscillator(zeta=0.05, vb=VB), Karnopp(FD, FS), None, 300.0, 1e-10),
    ("stribeck stick-slip", BeltOscillator(zeta=0.05, vb=VB), STRIBECK, None, 300.0, 1e-8),
    # a stable orbit without stick (multiplier ~0.75): the simulation converges slowly to it
    ("stribeck pure slip", BeltOscillator(zeta=0.34, vb=0.016), STRIBECK, (0.045, 0.0), 800.0, 1e-8),
]


@pytest.mark.parametrize("name,model,law,start,t_end,rtol", ATTRACTORS, ids=[a[0] for a in ATTRACTORS])
def test_shot_orbit_is_the_one_a_long_simulation_converges_to(name, model, law, start, t_end, rtol):
    x0, v0 = start if start else (None, None)
    # Newton from a guess that is not the simulation's end state (transient 0)
    orbit = find_orbit(model, law, x0=0.045 if start is None else 0.047, v0=0.0, transient=0.0)
    assert orbit.stable
    res = analyze(simulate(model, law, t_end=t_end, x0=x0, v0=v0))
    ss = res.steady_state
    assert ss.kind == "periodic"
    assert orbit.period == pytest.approx(ss.period, rel=100 * rtol)
    assert orbit.state[0] == pytest.approx(res.amplitude["X_max"], rel=100 * rtol)  # the section is the maximum of X
    assert orbit.measures.extremes["X_min"] == pytest.approx(res.amplitude["X_min"], abs=1e-6 * FS)
    assert orbit.stick_fraction == pytest.approx(ss.stick_fraction, abs=1e-6)
    for k in ("P_fin", "P_df", "P_dv"):
        assert getattr(orbit.measures.power, k) == pytest.approx(getattr(res.power, k), rel=1e-6)
    assert orbit.measures.TR_B == pytest.approx(res.TR_B, rel=1e-6)


def test_undamped_coulomb_orbit_matches_the_closed_form():
    # zeta = 0: slip on the circle about F_d through (F_s, V_b), stick from F_d - (F_s - F_d)
    # back to F_s at V_b.  No damper: all friction input goes back out through friction.
    model, law = BeltOscillator(zeta=0.0, vb=VB), Coulomb(FD, FS)
    orbit = find_orbit(model, law)
    r = math.hypot(FS - FD, VB)
    assert orbit.period == pytest.approx(math.pi + 2 * math.atan(VB / (FS - FD)) + 2 * (FS - FD) / VB, rel=1e-13)
    assert orbit.state[0] == pytest.approx(FD + r, rel=1e-13)
    assert orbit.stick_fraction * orbit.period == pytest.approx(2 * (FS - FD) / VB, rel=1e-12)
    assert orbit.measures.TR_B == pytest.approx((FD + r) / FD, rel=1e-12)
    p = orbit.measures.power
    assert p.P_dv == 0.0 and p.P_fin == pytest.approx(p.P_df, rel=1e-10) and p.R_f == pytest.approx(1.0, rel=1e-10)


def test_energy_balances_over_one_period():
    # periodic motion: what friction puts in, the damper and friction take out (P_fin = P_dv + P_df)
    for law, zeta in ((Coulomb(FD, FS), 0.05), (STRIBECK, 0.05)):
        o = find_orbit(BeltOscillator(zeta=zeta, vb=VB), law)
        p = o.measures.power
        assert p.P_fin == pytest.approx(p.P_dv + p.P_df, rel=1e-8)
        assert p.R_c + p.R_f == pytest.approx(1.0, rel=1e-8)


def test_unstable_orbit_found_from_a_guess():
    # between the subcritical Hopf point and the fold, an unstable slip-only cycle surrounds the
    # stable equilibrium: simulations never find it, shooting from a guess does
    model = BeltOscillator(zeta=0.3, vb=0.016)
    orbit = find_orbit(model, STRIBECK, x0=0.031, v0=0.0, transient=0.0)
    assert not orbit.has_stick and orbit.stability == "unstable" and orbit.multiplier.real > 1.5
    # and the simulation started on it leaves it (a check that "unstable" is meant)
    tr = simulate(model, STRIBECK, Adaptive(rtol=1e-12), t_end=150.0, x0=orbit.state[0] + 1e-6, v0=0.0)
    assert abs(tr.x[-1] - orbit.state[0]) > 1e-3


def test_deflation_keeps_newton_off_the_equilibrium():
    # close to the Hopf point the small cycle and the equilibrium are near each other
    model = BeltOscillator(zeta=0.25, vb=0.016)
    x_star = STRIBECK.sliding_equilibrium(0.016)
    orbit = shoot(model, STRIBECK, x_star + 1e-4)
    assert 1e-3 < orbit.state[0] - x_star < 2e-3
    assert orbit.multiplier.real == pytest.approx(1.0335, abs=1e-3)
    # where no cycle is near, Newton says so instead of "converging" onto X*
    with pytest.raises(ShootingError):
        shoot(BeltOscillator(zeta=0.4, vb=0.016), STRIBECK, x_star + 1e-3)


def test_no_orbit_when_the_simulation_settles():
    with pytest.raises(ShootingError):
        find_orbit(BeltOscillator(zeta=0.5, vb=VB), Coulomb(FD, FS), transient=200.0)


def test_counting_two_returns_gives_the_second_iterate():
    model = BeltOscillator(zeta=0.3, vb=0.016)
    one = shoot(model, STRIBECK, 0.031)
    two = shoot(model, STRIBECK, 0.031, returns=2)
    assert two.period == pytest.approx(2 * one.period, rel=1e-9)
    assert two.multiplier.real == pytest.approx(one.multiplier.real**2, rel=1e-6)


def test_report_is_json_with_all_multipliers():
    o = find_orbit(BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS))
    d = json.loads(json.dumps(o.to_dict(), allow_nan=False))
    assert {"period", "floquet_multipliers", "stable", "stick_fraction", "averages", "TR_B"} <= d.keys()
    assert len(d["floquet_multipliers"]) == 2 and all(len(m) == 2 for m in d["floquet_multipliers"])
    assert {"P_fin", "P_df", "P_dv", "R_c", "R_f"} <= d["averages"].keys()
