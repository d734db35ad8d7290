"""The sliding equilibrium along a parameter and its Hopf points, against 2 zeta + F'(V_b) = 0."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb, Karnopp, Stribeck, sliding_equilibrium
from frictionflow.orbits import continuation
from frictionflow.orbits.equilibria import equilibrium, equilibrium_branch, hopf_points

FD, FS, VS = 0.02, 0.04, 0.01


def slope(v, delta, cv):
    """F'(v) of F = F_d + (F_s - F_d) exp(-(v/V_s)^delta) + c_v v, differentiated by hand."""
    u = (v / VS) ** delta
    return -(FS - FD) * delta * u / v * math.exp(-u) + cv


def test_hopf_in_belt_speed_exponential_law_closed_form():
    # delta = 1: F'(v) = -(F_s-F_d)/V_s e^{-v/V_s} + c_v, so 2 zeta + F'(v_H) = 0 gives
    # v_H = V_s ln((F_s - F_d) / ((2 zeta + c_v) V_s))
    zeta, cv = 0.1, 0.05
    law = Stribeck(FD, FS, VS, delta=1.0, viscous=cv)
    res = continuation(BeltOscillator(zeta=zeta, vb=0.01), law, "vb", 0.005, 0.05, seeds=(), n_equilibria=31)
    hopf = [b for b in res.bifurcations if b.type == "hopf"]
    assert len(hopf) == 1
    assert hopf[0].value == pytest.approx(VS * math.log((FS - FD) / ((2 * zeta + cv) * VS)), rel=1e-12)
    # the equilibrium is unstable below it (F' more negative than -2 zeta) and stable above
    for p in res.branches[0].points:
        expected = "stable" if 2 * zeta + slope(p.value, 1.0, cv) > 0 else "unstable"
        if abs(p.value - hopf[0].value) > 1e-9:
            assert p.stability == expected


def test_hopf_in_damping_gaussian_law_closed_form():
    # delta = 2: zeta_H = -F'(V_b)/2 = (F_s - F_d) (V_b/V_s^2) e^{-(V_b/V_s)^2} - c_v/2
    vb, cv = 0.016, 0.02
    law = Stribeck(FD, FS, VS, delta=2.0, viscous=cv)
    found = hopf_points(BeltOscillator(zeta=0.1, vb=vb), law, "zeta", np.linspace(0.0, 0.5, 11))
    expected = (FS - FD) * (vb / VS**2) * math.exp(-((vb / VS) ** 2)) - cv / 2
    assert found == [pytest.approx(expected, rel=1e-12)]
    assert found[0] == pytest.approx(law.hopf_damping(vb), rel=1e-12)


def test_two_hopf_points_in_belt_speed_where_the_gaussian_law_falls_fastest():
    zeta = 0.4
    law = Stribeck(FD, FS, VS)
    found = hopf_points(BeltOscillator(zeta=zeta, vb=0.01), law, "vb", np.linspace(0.0005, 0.04, 41))
    g = lambda v: 2 * zeta + slope(v, 2.0, 0.0)
    v_min = VS / math.sqrt(2)  # where F' is most negative
    expected = [brentq(g, 0.0005, v_min, xtol=1e-15), brentq(g, v_min, 0.04, xtol=1e-15)]
    assert found == [pytest.approx(e, rel=1e-10) for e in expected]


def test_constant_friction_has_no_hopf_point():
    assert hopf_points(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(FD, FS), "vb", np.linspace(0.001, 0.05, 11)) == []
    eq = equilibrium(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(FD, FS))
    assert eq.x == FD and eq.stability == "stable"
    assert equilibrium(BeltOscillator(zeta=0.05, vb=0.0), Coulomb(FD, FS)) is None


def test_the_branch_is_made_of_the_analysis_equilibria():
    # one definition: the continuation's equilibria are those frictionflow.analyze reports
    model, law = BeltOscillator(zeta=0.1, vb=0.01), Stribeck(FD, FS, VS, delta=1.0, viscous=0.05)
    for eq in equilibrium_branch(model, law, "vb", np.linspace(0.005, 0.05, 7)):
        same = sliding_equilibrium(BeltOscillator(zeta=0.1, vb=eq.value), law)
        assert (eq.x, eq.damping, eq.eigenvalues) == (same.x, same.damping, same.eigenvalues)
        assert eq.stability == ("stable" if 2 * 0.1 + slope(eq.value, 1.0, 0.05) > 0 else "unstable")


def test_no_sliding_equilibrium_inside_karnopps_band():
    law = Karnopp(FD, FS, vd=1e-3)
    assert math.isnan(sliding_equilibrium(BeltOscillator(zeta=0.05, vb=5e-4), law).x)
    assert equilibrium(BeltOscillator(zeta=0.05, vb=5e-4), law) is None
    assert equilibrium(BeltOscillator(zeta=0.05, vb=0.01), law).x == FD
