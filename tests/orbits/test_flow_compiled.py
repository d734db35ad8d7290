"""The compiled DOP853 engine against the solve_ivp engine, the closed-form engine, finite differences
of itself in the parameters, and the package's adaptive solver for the work integrals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Cubic, Stribeck, simulate
from frictionflow.analysis.power_flow import power_flow
from frictionflow.orbits.flow import make_flow
from frictionflow.orbits.flow_compiled import CompiledFlow, equilibrium_slope
from frictionflow.orbits.parameters import get_param, parameter_names, with_param

#: (model, law, start X on the section): a slip-only unstable cycle, a stick-slip cycle, a cubic-law cycle
CASES = {
    "stribeck_slip": (BeltOscillator(zeta=0.3, vb=0.016), Stribeck(0.02, 0.04, 0.01), 0.031),
    "stribeck_stick": (BeltOscillator(zeta=0.05, vb=0.01), Stribeck(0.02, 0.04, 0.01), 0.045),
    "cubic": (BeltOscillator(zeta=0.05, vb=0.1), Cubic(0.04, 0.3, 10.0), 0.12),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_compiled_and_solve_ivp_engines_agree(name):
    model, law, x = CASES[name]
    a = make_flow(model, law, engine="compiled").run((x, 0.0), returns=1)
    b = make_flow(model, law, engine="smooth").run((x, 0.0), returns=1)
    assert a.modes == b.modes
    assert a.y1[0] == pytest.approx(b.y1[0], rel=1e-9)
    assert a.duration == pytest.approx(b.duration, rel=1e-9)
    np.testing.assert_allclose(a.section_jacobian(), b.section_jacobian(), rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose([s.t for s in a.switches], [s.t for s in b.switches], atol=1e-9)


def test_the_compiled_engine_reproduces_the_closed_form_coulomb_flow():
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04)
    a = make_flow(model, law, engine="exact").run((-0.2, 0.0), duration=20.0)
    b = make_flow(model, law, engine="compiled").run((-0.2, 0.0), duration=20.0)
    assert a.modes == b.modes and {"slip reversal", "stick onset", "slip onset"} <= {s.kind for s in a.switches}
    np.testing.assert_allclose(b.y1, a.y1, rtol=0, atol=1e-11)
    np.testing.assert_allclose(b.jacobian(), a.jacobian(), rtol=0, atol=1e-8)
    np.testing.assert_allclose([s.t for s in b.switches], [s.t for s in a.switches], atol=1e-11)


def _section_end(model, law, x, param=None):
    seg = CompiledFlow(model, law, param=param).run((x, 0.0), returns=1)
    return seg


@pytest.mark.parametrize("name", sorted(CASES))
def test_parameter_column_matches_central_differences(name):
    model, law, x = CASES[name]
    for param in parameter_names(law):
        if param not in ("vb", "zeta") and param not in {p.name for p in law.parameters}:
            continue
        seg = _section_end(model, law, x, param)
        cols = seg.section_columns()
        v = get_param(model, law, param)
        if v > 0:  # central differences
            h = 1e-6 * v
            ends = [_section_end(*with_param(model, law, param, v + s * h), x) for s in (1, -1)]
            dX = (ends[0].y1[0] - ends[1].y1[0]) / (2 * h)
            dT = (ends[0].duration - ends[1].duration) / (2 * h)
        else:  # at the lower bound 0: the second-order one-sided difference
            h = 1e-6
            e = [_section_end(*with_param(model, law, param, k * h), x) for k in (0, 1, 2)]
            dX = (-3 * e[0].y1[0] + 4 * e[1].y1[0] - e[2].y1[0]) / (2 * h)
            dT = (-3 * e[0].duration + 4 * e[1].duration - e[2].duration) / (2 * h)
        scale = max(abs(dX), 1e-3 * max(abs(x), 1.0))
        assert cols[0, 2] == pytest.approx(dX, abs=2e-6 * scale), param
        assert cols[1, 2] == pytest.approx(dT, rel=1e-5, abs=1e-5), param


@pytest.mark.parametrize("name", sorted(CASES))
def test_work_integrals_match_the_adaptive_solver_over_the_same_stretch(name):
    model, law, x = CASES[name]
    seg = CompiledFlow(model, law).run((x, 0.0), returns=1)
    traj = simulate(model, law, t_end=seg.duration, x0=x, v0=0.0)
    pf = power_flow(traj)
    assert seg.W_dv / seg.duration == pytest.approx(pf.P_dv, rel=1e-8)
    assert seg.W_fin / seg.duration == pytest.approx(pf.P_fin, rel=1e-8)


@pytest.mark.parametrize("name", sorted(CASES))
def test_work_integral_derivatives_match_central_differences(name):
    model, law, x = CASES[name]
    param = "vb"
    seg = CompiledFlow(model, law, param=param).run((x, 0.0), duration=7.0)
    v = model.vb
    h = 1e-6 * v
    runs = [CompiledFlow(*with_param(model, law, param, v + s * h)).run((x, 0.0), duration=7.0) for s in (1, -1)]
    hx = 1e-7
    runs_x = [CompiledFlow(model, law).run((x + s * hx, 0.0), duration=7.0) for s in (1, -1)]
    for w, dw in (("W_dv", "dW_dv"), ("W_fin", "dW_fin")):
        fd_l = (getattr(runs[0], w) - getattr(runs[1], w)) / (2 * h)
        fd_x = (getattr(runs_x[0], w) - getattr(runs_x[1], w)) / (2 * hx)
        d = getattr(seg, dw)
        assert d[2] == pytest.approx(fd_l, rel=1e-5, abs=1e-7), w
        assert d[0] == pytest.approx(fd_x, rel=1e-5, abs=1e-7), w


def test_equilibrium_slope_is_the_slip_curve_slope_and_partials():
    model, law = BeltOscillator(zeta=0.1, vb=0.02), Stribeck(0.02, 0.04, 0.01)
    # X* = F_d + (F_s - F_d) exp(-(V_b/V_s)^2): derived by hand
    u = (0.02 / 0.01) ** 2
    assert equilibrium_slope(model, law, "vb") == pytest.approx(-(0.02) * 2 * u / 0.02 * math.exp(-u), rel=1e-12)
    assert equilibrium_slope(model, law, "fs") == pytest.approx(math.exp(-u), rel=1e-12)
    assert equilibrium_slope(model, law, "zeta") == 0.0
