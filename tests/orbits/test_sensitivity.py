"""Exact slopes along branches against finite differences; folds and grazings located by Newton against
independent computations (dense branch sampling, a second formulation, brute-force simulations)."""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Exact, Stribeck, simulate
from frictionflow.orbits import continuation
from frictionflow.orbits.cycle_problem import CycleProblem
from frictionflow.orbits.flow_compiled import CompiledFlow
from frictionflow.orbits.sensitivity import (
    EXACT_MONITORS, locate_fold, locate_grazing, orbit_derivatives, stick_slip_grazing, stick_slip_margin,
)
from frictionflow.orbits.parameters import with_param
from frictionflow.orbits.shooting import newton

MODEL, LAW = BeltOscillator(zeta=0.3, vb=0.016), Stribeck(0.02, 0.04, 0.01)


def _orbit(model, law, x_guess):
    """A tightly converged fixed point of P (its own Newton, tolerance at rounding)."""
    flow = CompiledFlow(model, law)
    x, *_ = newton(flow, x_guess, x_star=law.sliding_equilibrium(model.vb), tol_abs=1e-14)
    return x


def _kernel_values(model, law, x):
    seg = CompiledFlow(model, law).run((x, 0.0), returns=1)
    T = seg.duration
    pdv, pfin = seg.W_dv / T, seg.W_fin / T
    return {"P_dv": pdv, "P_fin": pfin, "P_df": pfin - pdv, "R_c": pdv / pfin, "R_f": (pfin - pdv) / pfin,
            "period": T, "amplitude": 0.5 * (x - seg.x_min), "X": x}


@pytest.mark.parametrize("param,value,x", [("zeta", 0.3, 0.031), ("vb", 0.016, 0.031), ("vs", 0.01, 0.031)])
def test_power_slopes_along_the_branch_match_finite_differences(param, value, x):
    x0 = _orbit(MODEL, LAW, x)
    d = orbit_derivatives(MODEL, LAW, param, x0)
    h = 1e-5 * value
    ends = []
    for s in (1, -1):
        m, law = with_param(MODEL, LAW, param, value + s * h)
        ends.append(_kernel_values(m, law, _orbit(m, law, x0)))
    for k in EXACT_MONITORS:
        fd = (ends[0][k] - ends[1][k]) / (2 * h)
        assert d.slopes[k] == pytest.approx(fd, rel=2e-5, abs=1e-9 * max(abs(d.values[k]), 1e-6) / h), k


def test_power_values_match_the_package_solver():
    from frictionflow.orbits import shoot

    orbit = shoot(MODEL, LAW, 0.031)
    d = orbit_derivatives(MODEL, LAW, "zeta", orbit.state[0])
    av = orbit.measures.averages()
    for k in ("P_dv", "P_fin", "P_df", "R_c", "R_f"):
        assert d.values[k] == pytest.approx(av[k], rel=1e-7), k
    assert d.values["amplitude"] == pytest.approx(orbit.amplitude, rel=1e-7)


def test_fold_is_where_lambda_turns_on_a_densely_sampled_branch():
    lam_fold = None
    res = continuation(MODEL, LAW, "zeta", 0.2, 0.4, seeds=("hopf",), n_equilibria=21)
    fold = next(b for b in res.bifurcations if b.type == "fold")
    near = min(res.branches[1].points, key=lambda p: abs(p.value - fold.value))
    x_f, lam_fold = locate_fold(MODEL, LAW, "zeta", near.x, near.value)
    assert fold.value == pytest.approx(lam_fold, abs=1e-12)
    # independent: the branch sampled densely in X (each point a fixed zeta solved by bisection on P(X) = X)
    problem = CycleProblem(MODEL, LAW, "zeta", 0.2, 0.4)

    def zeta_of(x):
        lo, hi = lam_fold - 0.01, lam_fold + 1e-4  # G changes sign across the branch at fixed X
        g = lambda z: _kernel_g(z, x)
        glo, ghi = g(lo), g(hi)
        assert glo * ghi < 0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if (g(mid) < 0) == (glo < 0):
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)

    xs = x_f + np.linspace(-2e-4, 2e-4, 41)
    zs = np.array([zeta_of(x) for x in xs])
    assert zs.max() == pytest.approx(lam_fold, abs=1e-9)
    assert abs(xs[np.argmax(zs)] - x_f) <= 1e-5
    del problem


def _kernel_g(zeta, x):
    m, law = with_param(MODEL, LAW, "zeta", zeta)
    px, *_ = CompiledFlow(m, law).poincare(x)
    return px - x


def test_slip_only_and_stick_slip_formulations_of_the_grazing_agree():
    res = continuation(MODEL, LAW, "zeta", 0.2, 0.4, seeds=("hopf",), n_equilibria=21)
    graze = next(b for b in res.bifurcations if b.type == "grazing")
    assert graze.detail["refined"]
    other = stick_slip_grazing(MODEL, LAW, "zeta", 0.3, 0.34)
    assert graze.value == pytest.approx(other, abs=1e-10)


def _sticks_for_good(vb, zeta):
    """Brute force: does a long exact simulation still stick at its end?"""
    traj = simulate(BeltOscillator(zeta=zeta, vb=vb), Coulomb(0.02, 0.04), Exact(), t_end=400.0)
    return bool(np.any(traj.mode[-len(traj.mode) // 4:] == 0))


@pytest.mark.parametrize("zeta", [0.02, 0.05])
def test_coulomb_stick_slip_grazing_matches_bisection_on_simulations(zeta):
    model, law = BeltOscillator(zeta=zeta, vb=0.01), Coulomb(0.02, 0.04)
    vb_g = stick_slip_grazing(model, law, "vb", 0.001, 0.2)
    lo, hi = 0.001, 0.2
    assert _sticks_for_good(lo, zeta) and not _sticks_for_good(hi, zeta)
    for _ in range(24):
        mid = 0.5 * (lo + hi)
        if _sticks_for_good(mid, zeta):
            lo = mid
        else:
            hi = mid
    assert vb_g == pytest.approx(0.5 * (lo + hi), abs=2e-7)
    g, dg = stick_slip_margin(*with_param(model, law, "vb", vb_g), "vb")
    assert abs(g) < 1e-12


def test_grazing_slope_matches_finite_differences():
    model, law = BeltOscillator(zeta=0.05, vb=0.03), Coulomb(0.02, 0.04)
    for param in ("vb", "zeta", "fs", "fd"):
        g, dg = stick_slip_margin(model, law, param)
        v = float(getattr(model if param in ("vb", "zeta") else law, param))
        h = 1e-6 * v
        gp = stick_slip_margin(*with_param(model, law, param, v + h), param)[0]
        gm = stick_slip_margin(*with_param(model, law, param, v - h), param)[0]
        assert dg == pytest.approx((gp - gm) / (2 * h), rel=1e-5), param


def test_locate_grazing_touches_v_b():
    x, lam = locate_grazing(MODEL, LAW, "zeta", 0.0447, 0.33)
    m, law = with_param(MODEL, LAW, "zeta", lam)
    seg = CompiledFlow(m, law, virtual=True).run((x, 0.0), returns=1)
    assert seg.y1[0] == pytest.approx(x, abs=1e-12)
    assert abs(seg.vr_min) < 1e-12
    # the real flow: a cycle that just touches (no stick phase worth the name)
    assert CompiledFlow(m, law).run((x, 0.0), returns=1).stick_time < 1e-4
