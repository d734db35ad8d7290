"""Monitors along forced branches (against closed forms and dense sampling), extrema continued in the second
forcing parameter (against point-wise one-parameter runs), and (Omega, F_ex) curves (against brute force and
continuations in the other parameter)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Cubic, Stribeck
from frictionflow.core import tangent
from frictionflow.orbits.forced import continue_forced, find_forced_orbit
from frictionflow.orbits.forced_chart import (
    FORCED_MONITORS,
    continue_forced_extremum,
    forced_branch_extrema,
    forced_chart,
    forced_monitor,
    forced_monitor_value,
)
from frictionflow.orbits.monitors import branch_extrema, monitor_value
from frictionflow.orbits.settings import ForcedContinuationSettings
from frictionflow.solvers.base import kernel_params

ZETA, FD, FEX = 0.05, 0.5, 0.1
# V_b far above every X': always slip+, the friction force the constant F_d -- the linear oscillator, shifted
LINEAR = BeltOscillator(zeta=ZETA, vb=10.0, fex=FEX, omega=0.8)
LINEAR_LAW = Coulomb(FD, 1.0)
# a Coulomb belt whose harmonic orbit slips near resonance and sticks away from it
SLIPPY = BeltOscillator(zeta=0.1, vb=0.5, fex=0.3, omega=0.9)
SLIPPY_LAW = Coulomb(0.1, 0.15)


@pytest.fixture(scope="module")
def linear_branch():
    return continue_forced(LINEAR, LINEAR_LAW, "omega", 0.8, 1.2)


def linear_amplitude(omega: float) -> float:
    return FEX / math.hypot(1.0 - omega**2, 2.0 * ZETA * omega)


def test_every_monitor_on_the_linear_branch_is_the_closed_form(linear_branch):
    """X = F_d + A cos(Omega tau - theta): P_ex = P_dv = zeta Omega^2 A^2, TR_B = (F_d + A sqrt(1 + 4 zeta^2 Omega^2)) / F_ex."""
    for p in linear_branch.points:
        w, A = p.lam, linear_amplitude(p.lam)
        assert monitor_value(p, "P_ex") == pytest.approx(ZETA * w**2 * A**2, rel=1e-6)
        assert forced_monitor_value(p, "P_dv") == pytest.approx(ZETA * w**2 * A**2, rel=1e-6)
        assert forced_monitor_value(p, "amplitude") == pytest.approx(A, rel=1e-6)
        assert forced_monitor_value(p, "TR_B") == pytest.approx((FD + A * math.hypot(1.0, 2 * ZETA * w)) / FEX, rel=1e-6)
        assert forced_monitor_value(p, "stick_fraction") == 0.0
    assert set(FORCED_MONITORS) >= {"P_ex", "P_dv", "P_fin", "P_df", "R_c", "R_f", "TR_B", "amplitude", "stick_fraction"}
    with pytest.raises(ValueError, match="monitor"):
        forced_monitor(linear_branch, "period")


def test_extrema_on_the_linear_branch_are_the_resonances(linear_branch):
    """Input power peaks at Omega = 1 exactly (velocity resonance), the amplitude at sqrt(1 - 2 zeta^2), and
    TR_B where a u^2 + 2u - 2 = 0 (u = Omega^2, a = 4 zeta^2: d/du of (1 + a u) / ((1 - u)^2 + a u) = 0)."""
    a = 4 * ZETA**2
    closed = {"P_ex": 1.0, "P_dv": 1.0, "amplitude": math.sqrt(1 - 2 * ZETA**2),
              "TR_B": math.sqrt((-1 + math.sqrt(1 + 2 * a)) / a)}
    for monitor, omega in closed.items():
        (e,) = branch_extrema(linear_branch, monitor)  # the generic entry point dispatches on the forced branch
        assert e.kind == "max" and e.method == "brent"
        assert e.value == pytest.approx(omega, abs=1e-7), monitor
    # constant along the branch (P_belt = F_d V_b in pure slip): rounding, not extrema
    assert forced_branch_extrema(linear_branch, "P_belt") == []
    assert forced_branch_extrema(linear_branch, "stick_fraction") == []


def _dense(model, law, lam_values, start, monitor, m=1):
    """The monitor at each lambda (Omega), each orbit found anew by Newton shooting from the last one."""
    out, P = [], np.asarray(start, dtype=float)
    for lam in lam_values:
        o = find_forced_orbit(replace(model, omega=float(lam)), law, m, float(P[0]), float(P[1]))
        P = o.state
        out.append(forced_monitor_value(o, monitor))
    return np.array(out)


def test_tr_b_maximum_matches_dense_sampling_of_the_branch():
    branch = continue_forced(SLIPPY, SLIPPY_LAW, "omega", 0.9, 1.1)
    (e,) = forced_branch_extrema(branch, "TR_B")
    assert e.kind == "max" and 0.95 < e.value < 1.0 and "at" not in e.extra
    lams = np.linspace(e.value - 2e-3, e.value + 2e-3, 201)
    m = _dense(SLIPPY, SLIPPY_LAW, lams, (e.x, e.extra["V"]), "TR_B")
    k = int(np.argmax(m))
    assert 0 < k < len(lams) - 1 and abs(lams[k] - e.value) <= lams[1] - lams[0]
    c = np.polyfit(lams[k - 3:k + 4] - e.value, m[k - 3:k + 4], 2)  # the vertex of the parabola through the top
    assert -c[1] / (2 * c[0]) == pytest.approx(0.0, abs=2e-6)
    assert e.monitor_value >= m.max() - 1e-10


def test_extremum_on_a_grazing_corner_matches_dense_sampling():
    """On the Stribeck branch the input power has a minimum with a corner where a stick phase appears."""
    model, law = BeltOscillator(zeta=0.03, vb=0.12, fex=0.02, omega=0.9), Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0)
    branch = continue_forced(model, law, "omega", 0.9, 0.94)
    graze = [g for g in branch.events_of("grazing") if g.detail.get("stick_phase") == "appears"][0]
    (e,) = [x for x in forced_branch_extrema(branch, "P_ex") if x.extra.get("at") == "grazing corner"]
    assert e.kind == "min" and e.value == pytest.approx(graze.lam, abs=1e-6)
    lams = np.linspace(e.value - 1e-3, e.value + 1e-3, 101)
    m = _dense(model, law, lams, (e.x, e.extra["V"]), "P_ex")
    assert abs(lams[int(np.argmin(m))] - e.value) <= lams[1] - lams[0]
    assert e.monitor_value <= m.min() + 1e-12


def test_continued_extremum_matches_point_wise_runs():
    """The forcing frequency of greatest TR_B as F_ex varies: followed from F_ex = 0.3, and at each F_ex found
    afresh by a continuation in Omega and its refined extremum."""
    branch = continue_forced(SLIPPY, SLIPPY_LAW, "omega", 0.9, 1.1)
    (start,) = forced_branch_extrema(branch, "TR_B")
    values = [0.31, 0.33, 0.36]
    followed = continue_forced_extremum(SLIPPY, SLIPPY_LAW, "TR_B", "omega", 0.9, 1.1, "fex", values, start)
    assert [f.extra["fex"] for f in followed] == values
    for f in followed:
        b = continue_forced(replace(SLIPPY, fex=f.extra["fex"]), SLIPPY_LAW, "omega", 0.9, 1.1)
        (pw,) = forced_branch_extrema(b, "TR_B")
        assert f.value == pytest.approx(pw.value, abs=1e-7)
        assert f.monitor_value == pytest.approx(pw.monitor_value, rel=1e-10)
    assert abs(followed[-1].value - start.value) > 1e-3  # the extremum moves with F_ex


# -- curves in (Omega, F_ex) ------------------------------------------------------------------------------------------
SUB_LAW = Coulomb(0.5, 1.0)
SUB = BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.8)  # a period-2 stick-slip orbit, doubling at Omega ~ 1.6995


@pytest.fixture(scope="module")
def pd_chart():
    return forced_chart(SUB, SUB_LAW, "omega", (1.5, 2.2), "fex", [0.45, 0.5], m=2, x_start=1.8)


def _map_end(model, law, P, periods):
    """Brute force: the state after ``periods`` forcing periods from P (RK4 with located switches)."""
    p = kernel_params(model, law)
    strobe, est = np.zeros((periods, 3)), np.zeros((periods, 2))
    counts = np.zeros(tangent.N_COUNTS, dtype=np.int64)
    status, _, _ = tangent.run(float(P[0]), float(P[1]), model.zeta, model.vb, p, model.forcing_period, 512, 0, periods,
                               strobe, est, counts)
    assert status == tangent.OK
    return strobe[-1, :2]


def test_period_doubling_curve_against_brute_force(pd_chart):
    pd = pd_chart.curve("period_doubling", m=2)
    assert [p.y for p in pd.points] == [0.45, 0.5]
    assert pd.points[1].x == pytest.approx(1.6995, abs=1e-4)  # the known point at F_ex = 0.5
    point = pd.points[0]
    # across the curve at fixed Omega, the brute-force deviation ratio of the 2-period map along the doubling
    # eigenvector passes -1: > -1 on one side, < -1 on the other
    ratios = []
    for d in (-3e-3, 3e-3):
        model = replace(SUB, omega=point.x, fex=point.y + d)
        o = find_forced_orbit(model, SUB_LAW, 2, point.detail["X"], point.detail["V"])
        w, vecs = np.linalg.eig(o.monodromy)
        e = np.real(vecs[:, int(np.argmin(np.abs(w + 1.0)))])
        eps = 1e-6
        ratio = float((_map_end(model, SUB_LAW, o.state + eps * e, 2) - _map_end(model, SUB_LAW, o.state - eps * e, 2)) @ e
                      / (2 * eps))
        assert ratio == pytest.approx(float(np.real(w[np.argmin(np.abs(w + 1.0))])), abs=1e-6)
        ratios.append(ratio)
    assert min(ratios) < -1.0 < max(ratios) and max(abs(r + 1.0) for r in ratios) < 0.05


def test_period_doubling_curve_crossed_by_a_continuation_in_f_ex(pd_chart):
    """At fixed Omega on the curve, a continuation in F_ex meets the doubling at the curve's F_ex."""
    point = pd_chart.curve("period_doubling", m=2).points[0]
    model = replace(SUB, omega=point.x, fex=0.5)
    o = find_forced_orbit(model, SUB_LAW, 2, transient_periods=400)
    branch = continue_forced(model, SUB_LAW, "fex", 0.5, 0.4, m=2, orbit=o)
    (pd,) = branch.events_of("period_doubling")
    assert pd.lam == pytest.approx(point.y, abs=1e-7)


def test_fold_curve_of_the_locking_tongue_crossed_by_a_continuation_in_f_ex():
    """A self-excited cubic-law oscillator locked 1:1 by weak forcing: folds at the edge of its tongue.  The fold
    point found continuing in Omega at F_ex = 1.3e-4 is met again continuing in F_ex at that Omega."""
    law = Cubic(fs=0.3, k1=0.3, k3=10.0)
    model = BeltOscillator(zeta=0.05, vb=0.08, fex=5e-4, omega=1.001)
    start = find_forced_orbit(model, law, m=1, transient_periods=600)
    along = continue_forced(model, law, "fex", 5e-4, 1e-4, m=1, orbit=start)
    near = min(along.points, key=lambda q: abs(q.lam - 1.3e-4))
    chart = forced_chart(model, law, "omega", (0.99, 1.012), "fex", [1.3e-4], x_start=1.001, guess=near.state)
    folds = chart.curve("fold", m=1).points
    assert len(folds) == 2 and all(0.99 < p.x < 1.0 for p in folds)
    assert chart.curve("neimark_sacker", m=1) is not None  # the tongue's other edge at this F_ex
    fp = folds[0]
    o = find_forced_orbit(replace(model, omega=fp.x), law, x0=fp.detail["X"], v0=fp.detail["V"], transient_periods=300)
    cross = continue_forced(replace(model, omega=fp.x), law, "fex", 5e-4, 1e-5, orbit=o)
    assert min(abs(e.lam - fp.y) for e in cross.events_of("fold")) < 1e-10
    # the chart's data round-trips
    assert chart.to_dict()["curves"][0]["m"] == 1
    ds = chart.to_xarray()
    assert np.allclose(sorted(ds["fold_m1_omega"].values[0]), sorted(p.x for p in folds))


def test_forced_continuations_take_their_settings_as_a_record_or_as_keywords():
    """continue_forced and forced_chart: a ForcedContinuationSettings or its fields as keywords, the same branch and
    chart; any other keyword refused by name."""
    record = ForcedContinuationSettings(steps=128, max_points=6)
    by_keywords = continue_forced(LINEAR, LINEAR_LAW, "omega", 0.8, 1.2, steps=128, max_points=6)
    by_record = continue_forced(LINEAR, LINEAR_LAW, "omega", 0.8, 1.2, settings=record)
    assert by_record.settings == by_keywords.settings and by_record.settings["steps_per_period"] == 128
    assert len(by_record) == len(by_keywords) == 6
    np.testing.assert_array_equal([p.state for p in by_record.points], [p.state for p in by_keywords.points])
    np.testing.assert_array_equal(by_record.lam, by_keywords.lam)
    plane = (LINEAR, LINEAR_LAW, "omega", (0.8, 1.2), "fex", [FEX])
    chart = forced_chart(*plane, x_start=0.8, continuation=record)
    assert chart.to_dict() == forced_chart(*plane, x_start=0.8, steps=128, max_points=6).to_dict()
    assert [r.points for r in chart.runs] == [6]
    with pytest.raises(TypeError, match=r"continue_forced\(\) got an unexpected keyword argument 'hmax'"):
        continue_forced(LINEAR, LINEAR_LAW, "omega", 0.8, 1.2, hmax=0.1)
    with pytest.raises(TypeError, match=r"forced_chart\(\) got an unexpected keyword argument 'hmax'"):
        forced_chart(*plane, hmax=0.1)
    with pytest.raises(TypeError, match="continuation must be a ForcedContinuationSettings"):
        forced_chart(*plane, continuation={"steps": 128})
