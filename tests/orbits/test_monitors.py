"""Monitor extrema along branches against dense sampling of the branch, and continued extrema against
point-wise one-parameter runs."""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import BeltOscillator, Cubic
from frictionflow.orbits import continuation
from frictionflow.orbits.cycle_problem import CycleProblem
from frictionflow.orbits.monitors import MONITORS, branch_extrema, continue_extremum, monitor_value
from frictionflow.orbits.branches import BranchPoint
from frictionflow.orbits.parameters import with_param
from frictionflow.orbits.shooting import orbit_from_segment

MODEL, LAW = BeltOscillator(zeta=0.05, vb=0.1), Cubic(0.04, 0.3, 10.0)


@pytest.fixture(scope="module")
def cubic_branch():
    return continuation(MODEL, LAW, "vb", 0.01, 0.3, seeds=("hopf",))


def _dense(model, law, lo, hi, x_guess, monitor, n):
    """The monitor at n values of V_b, each orbit solved anew and measured by the package's solver."""
    problem = CycleProblem(model, law, "vb", lo, hi)
    lams = np.linspace(lo, hi, n)
    out = []
    xi = x_guess - problem.system(lo)[2]
    for lam in lams:
        s = problem.solve_at(float(lam), xi)
        xi = s.xi
        orbit = orbit_from_segment(s.model, s.law, s.seg, residual=s.G, iterations=0)
        out.append(monitor_value(BranchPoint.from_orbit(float(lam), orbit), monitor))
    return lams, np.array(out)


def test_r_c_maximum_matches_dense_sampling_of_the_branch(cubic_branch):
    (e,) = branch_extrema(cubic_branch, "R_c", MODEL, LAW)
    assert e.kind == "max" and e.method == "slope root"
    lo, hi = e.value - 2e-3, e.value + 2e-3
    lams, m = _dense(MODEL, LAW, lo, hi, e.x, "R_c", 201)
    k = int(np.argmax(m))
    assert 0 < k < len(lams) - 1
    assert abs(lams[k] - e.value) <= lams[1] - lams[0]
    # the vertex of the parabola through the top samples
    c = np.polyfit(lams[k - 3:k + 4] - e.value, m[k - 3:k + 4], 2)
    assert -c[1] / (2 * c[0]) == pytest.approx(0.0, abs=2e-6)
    assert e.monitor_value == pytest.approx(m.max(), rel=1e-7)
    assert e.monitor_value >= m.max() - 1e-9


def test_extrema_on_a_grazing_corner_sit_at_the_grazing(cubic_branch):
    graze = next(b for b in cubic_branch.bifurcations if b.type == "grazing")
    assert graze.detail.get("refined")
    for monitor in ("TR_B", "P_fin", "amplitude"):
        (e,) = branch_extrema(cubic_branch, monitor, MODEL, LAW)
        assert e.kind == "max" and e.extra.get("at") == "grazing corner"
        assert e.value == pytest.approx(graze.value, abs=1e-12)
        pts = cubic_branch.branches[e.branch].points
        assert e.monitor_value >= max(monitor_value(p, monitor) for p in pts) - 1e-9 * abs(e.monitor_value)


def test_every_monitor_has_a_value_on_every_orbit(cubic_branch):
    for p in cubic_branch.branches[1].points:
        for monitor in MONITORS:
            assert np.isfinite(monitor_value(p, monitor)), monitor


def test_continued_extremum_matches_point_wise_one_parameter_runs(cubic_branch):
    (start,) = branch_extrema(cubic_branch, "R_c", MODEL, LAW)
    zetas = [0.05, 0.045, 0.04]
    curve = continue_extremum(MODEL, LAW, "R_c", "vb", 0.01, 0.3, "zeta", zetas, start)
    assert [e.extra["zeta"] for e in curve] == zetas
    for e in curve[1:]:
        m, law = with_param(MODEL, LAW, "zeta", e.extra["zeta"])
        run = continuation(m, law, "vb", 0.01, 0.3, seeds=("hopf",))
        (own,) = branch_extrema(run, "R_c", m, law)
        assert e.value == pytest.approx(own.value, abs=1e-10)
        assert e.monitor_value == pytest.approx(own.monitor_value, rel=1e-8)  # orbits converged to Newton's 1e-9
