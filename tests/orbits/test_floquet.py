"""Floquet multipliers from saltation matrices: stick phases, and finite-difference monodromy."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import trapezoid

from frictionflow import Adaptive, BeltOscillator, Coulomb, Exact, Karnopp, Stribeck
from frictionflow.orbits import fd_monodromy, find_orbit, make_flow, shoot
from frictionflow.orbits.floquet import classify

FD, FS, VB = 0.02, 0.04, 0.01
STRIBECK = Stribeck(FD, FS, 0.01)

STICK_ORBITS = [
    ("coulomb", BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS), 1e-13),
    ("karnopp", BeltOscillator(zeta=0.05, vb=VB), Karnopp(FD, FS), 1e-13),
    ("stribeck", BeltOscillator(zeta=0.05, vb=VB), STRIBECK, 1e-9),
]


@pytest.mark.parametrize("name,model,law,tol", STICK_ORBITS, ids=[s[0] for s in STICK_ORBITS])
def test_a_stick_phase_makes_the_nontrivial_multiplier_zero(name, model, law, tol):
    """While the mass sticks, X' = V_b whatever it was, so a perturbation of X' is erased
    (the stick-onset saltation matrix is diag(1, 0)); what is left of a perturbation of X
    only moves the end of the stick phase in time -- a shift along the orbit.  So the
    multipliers are exactly 1 (the trivial one) and 0: nearby motions land on the orbit
    within one period."""
    orbit = find_orbit(model, law)
    assert orbit.has_stick
    onset = [s for s in orbit.segment.switches if s.kind == "stick onset"]
    assert onset and np.allclose(onset[0].saltation, [[1, 0], [0, 0]], atol=1e-15)
    mu = orbit.multipliers
    assert abs(mu[0] - 1.0) < 1e-9 and abs(mu[1]) < tol
    assert orbit.stable and classify(orbit.multiplier) == "stable"
    # finite differences of the package's own solvers see the same rank-one monodromy
    solver = Adaptive(rtol=1e-12) if not law.piecewise_constant else Exact()
    M_fd = fd_monodromy(model, law, orbit.state, orbit.period, solver=solver)
    np.testing.assert_allclose(orbit.monodromy, M_fd, atol=1e-6)
    assert abs(np.linalg.det(M_fd)) < 1e-6


def test_superstability_two_starts_return_to_the_same_point():
    # the Poincare map is constant across starts that stick: not just a small slope, none
    flow = make_flow(BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS))
    p1 = flow.run((0.045, 0.0), returns=1).y1[0]
    p2 = flow.run((0.050, 0.0), returns=1).y1[0]
    assert p1 == pytest.approx(p2, abs=1e-15)


PURE_SLIP = [
    ("unstable (zeta 0.30)", 0.30, 0.031, "unstable"),
    ("stable (zeta 0.34)", 0.34, 0.0425, "stable"),
]


@pytest.mark.parametrize("name,zeta,guess,stability", PURE_SLIP, ids=[p[0] for p in PURE_SLIP])
def test_monodromy_of_a_pure_slip_orbit_matches_finite_differences(name, zeta, guess, stability):
    model = BeltOscillator(zeta=zeta, vb=0.016)
    orbit = shoot(model, STRIBECK, guess)
    assert not orbit.has_stick and orbit.stability == stability
    # central differences (step 4e-7) of simulations at rtol 1e-12: error ~1e-8 expected
    M_fd = fd_monodromy(model, STRIBECK, orbit.state, orbit.period, eps=1e-5 * FS, solver=Adaptive(rtol=1e-12))
    np.testing.assert_allclose(orbit.monodromy, M_fd, rtol=0, atol=1e-7)
    # the flow direction at the section point is the trivial eigenvector (multiplier 1) ...
    f0 = np.array([0.0, STRIBECK.sliding_equilibrium(0.016) - orbit.state[0]])
    np.testing.assert_allclose(orbit.monodromy @ f0, f0, atol=1e-10 * np.abs(f0).max())
    # ... and the other multiplier is det M (2-d), the slope of the Poincare map
    assert orbit.multiplier.real == pytest.approx(np.linalg.det(M_fd), rel=1e-6)
    assert orbit.multiplier.real == pytest.approx(orbit.segment.section_jacobian()[0, 0], rel=1e-9)


def test_divergence_formula_for_a_pure_slip_orbit():
    # Liouville: det M = exp(int div f dt) = exp(-int (2 zeta + F'(|V_r|)) dt) along the slip phase;
    # integrated here on the simulated period by the trapezoidal rule on a fine grid
    model = BeltOscillator(zeta=0.34, vb=0.016)
    orbit = shoot(model, STRIBECK, 0.0425)
    tr = orbit.trajectory(dense_dt=orbit.period / 20000, solver=Adaptive(rtol=1e-12, dense_dt=orbit.period / 20000))
    div = -(2 * model.zeta + np.array([STRIBECK.slip_slope(s) for s in 0.016 - tr.v]))
    assert orbit.multiplier.real == pytest.approx(np.exp(trapezoid(div, tr.t)), rel=1e-6)
