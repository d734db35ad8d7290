"""Flow maps with Jacobians: closed-form (exact) and solve_ivp (smooth) engines against each other,
against finite differences of the package's solvers, and against closed forms derived here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import (
    Adaptive,
    BeltOscillator,
    Coulomb,
    Exact,
    Karnopp,
    Stribeck,
    simulate,
)
from frictionflow.orbits.flow import make_flow

FD, FS, VB = 0.02, 0.04, 0.01


def fd_flow_jacobian(model, law, y0, T, solver, h):
    """Central differences of the time-T map, by simulate()."""
    cols = []
    for e in np.eye(2):
        ends = []
        for s in (1, -1):
            tr = simulate(model, law, solver, t_end=T, x0=y0[0] + s * h * e[0], v0=y0[1] + s * h * e[1])
            ends.append(np.array([tr.x[-1], tr.v[-1]]))
        cols.append((ends[0] - ends[1]) / (2 * h))
    return np.column_stack(cols)


@pytest.mark.parametrize("engine", ["exact", "smooth"])
def test_undamped_coulomb_stick_slip_matches_the_closed_form(engine):
    # zeta = 0: stick from X = F_d - r to F_s ... derived: the slip circle about F_d through
    # (F_s, V_b) has radius r = sqrt((F_s-F_d)^2 + V_b^2); slip lasts 2 pi - 2 atan((F_s-F_d)/V_b)
    # ... = pi + 2 atan(V_b/(F_s-F_d)); stick lasts 2 (F_s - F_d) / V_b.
    model, law = BeltOscillator(zeta=0.0, vb=VB), Coulomb(FD, FS)
    flow = make_flow(model, law, engine=engine)
    seg = flow.run((0.05, 0.0), returns=1)  # a circle of radius > V_b: it sticks, and after that is on the orbit
    seg = flow.run((seg.y1[0], 0.0), returns=1)
    r = math.hypot(FS - FD, VB)
    assert seg.y1[0] == pytest.approx(FD + r, rel=1e-12 if engine == "exact" else 1e-9)
    assert seg.duration == pytest.approx(math.pi + 2 * math.atan(VB / (FS - FD)) + 2 * (FS - FD) / VB, rel=1e-12 if engine == "exact" else 1e-9)
    assert seg.stick_time == pytest.approx(2 * (FS - FD) / VB, rel=1e-12 if engine == "exact" else 1e-9)
    assert seg.modes == ("slip+", "stick", "slip+")


def test_the_two_engines_agree_on_a_coulomb_flow_with_reversals_and_stick():
    model, law = BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS)
    a = make_flow(model, law, engine="exact").run((-0.2, 0.0), duration=20.0)
    b = make_flow(model, law, engine="smooth").run((-0.2, 0.0), duration=20.0)
    assert a.modes == b.modes and {"slip reversal", "stick onset", "slip onset"} <= {s.kind for s in a.switches}
    np.testing.assert_allclose(b.y1, a.y1, rtol=0, atol=1e-10)
    np.testing.assert_allclose(b.jacobian(), a.jacobian(), rtol=0, atol=1e-7)
    np.testing.assert_allclose([s.t for s in b.switches], [s.t for s in a.switches], atol=1e-9)


def test_reversal_saltation_is_the_ratio_of_accelerations():
    # crossing X' = V_b from slip+ to slip- (|F_e| > F_s): X'' jumps from +F_d - X - 2 zeta V_b
    # to -F_d - X - 2 zeta V_b; only the X' component is rescaled by their ratio.
    model, law = BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS)
    seg = make_flow(model, law).run((-0.2, 0.0), duration=5.0)
    sw = next(s for s in seg.switches if s.kind == "slip reversal")
    x = sw.y[0]
    a_before = FD - x - 2 * 0.05 * VB
    a_after = -FD - x - 2 * 0.05 * VB
    np.testing.assert_allclose(sw.saltation, [[1, 0], [0, a_after / a_before]], rtol=1e-13, atol=1e-15)


def test_slip_onset_saltation_of_coulomb():
    # leaving stick at F_e = F_s: X'' jumps from 0 to F_d - F_s, and the exit time moves by -dX/V_b
    model, law = BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS)
    seg = make_flow(model, law).run((0.0, VB), duration=10.0)
    sw = next(s for s in seg.switches if s.kind == "slip onset")
    np.testing.assert_allclose(sw.saltation, [[1, 0], [(FD - FS) / VB, 1]], rtol=1e-12)


CASES = [
    ("coulomb through reversals", BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS), (-0.2, 0.0), 7.0, Exact()),
    ("coulomb reversals + stick", BeltOscillator(zeta=0.05, vb=VB), Coulomb(FD, FS), (-0.2, 0.0), 20.0, Exact()),
    ("karnopp band modes", BeltOscillator(zeta=0.05, vb=VB), Karnopp(FD, FS), (-0.2, 0.0), 20.0, Exact()),
    ("karnopp spring stick force", BeltOscillator(zeta=0.1, vb=VB), Karnopp(FD, FS, stick_force="spring"), (-0.1, 0.0), 20.0, Exact()),
    ("stribeck reversals + stick", BeltOscillator(zeta=0.05, vb=VB), Stribeck(FD, FS, 0.01), (-0.2, 0.0), 20.0, Adaptive(rtol=1e-12)),
]


@pytest.mark.parametrize("name,model,law,y0,T,solver", CASES, ids=[c[0] for c in CASES])
def test_flow_jacobian_matches_finite_differences(name, model, law, y0, T, solver):
    seg = make_flow(model, law).run(y0, duration=T)
    assert len(seg.switches) >= 3
    J_fd = fd_flow_jacobian(model, law, y0, T, solver, h=1e-6)
    J = seg.jacobian()
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=2e-5 * max(1.0, np.abs(J).max()))


def test_a_shallow_crossing_between_integrator_steps_is_not_missed():
    # a slip circle that exceeds V_b by 1e-9 spends ~1e-3 time units above it -- far less than a
    # DOP853 step -- yet it must stick there, as the closed-form engine (which brackets every
    # extremum) says
    model, law = BeltOscillator(zeta=0.0, vb=VB), Coulomb(FD, FS)
    y0 = (FD + VB + 1e-9, 0.0)
    a = make_flow(model, law, engine="exact").run(y0, duration=10.0)
    b = make_flow(model, law, engine="smooth").run(y0, duration=10.0)
    assert a.modes == b.modes == ("slip+", "stick", "slip+")
    np.testing.assert_allclose([s.t for s in b.switches], [s.t for s in a.switches], atol=1e-7)
    np.testing.assert_allclose(b.y1, a.y1, atol=1e-9)


def test_laws_without_a_finite_slope_at_rest_are_refused():
    # delta < 1: F'(V_r) -> -inf as V_r -> 0, so the variational equations have no meaning there
    with pytest.raises(ValueError, match="infinite slope"):
        make_flow(BeltOscillator(zeta=0.05, vb=VB), Stribeck(FD, FS, 0.01, delta=0.5))


@pytest.mark.parametrize("name,model,law,y0,T,solver", CASES, ids=[c[0] for c in CASES])
def test_no_switch_flips_orientation(name, model, law, y0, T, solver):
    # det S = (grad h . f+) / (grad h . f-): positive for crossings, 0 into stick -- so the
    # nontrivial multiplier of any orbit is >= 0 and period doubling cannot occur
    seg = make_flow(model, law).run(y0, duration=T)
    for sw in seg.switches:
        det = np.linalg.det(sw.saltation)
        assert det >= -1e-12
        assert det == pytest.approx((sw.normal @ sw.f_after) / (sw.normal @ sw.f_before), abs=1e-12)
