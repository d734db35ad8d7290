"""Two-parameter curves against closed forms derived here, brute-force simulations and one-parameter runs."""

from __future__ import annotations

import math
import tempfile

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Exact, Stribeck, simulate
from frictionflow.orbits import continuation
from frictionflow.cli import main
from frictionflow.friction.registry import law_class, law_names
from frictionflow.orbits.chart import grazing_curve, hopf_curve, stability_chart, stability_map
from frictionflow.orbits.parameters import with_param
from frictionflow.orbits.sensitivity import stick_slip_margin

FD, FS, VS = 0.02, 0.04, 0.01
MODEL, LAW = BeltOscillator(zeta=0.3, vb=0.016), Stribeck(FD, FS, VS)


def stribeck_slope(s):
    """F'(s) of F = F_d + (F_s - F_d) exp(-(s/V_s)^2), by hand: -(F_s - F_d) 2 s / V_s^2 exp(-(s/V_s)^2)."""
    return -(FS - FD) * 2.0 * s / VS**2 * math.exp(-((s / VS) ** 2))


def test_stribeck_hopf_curve_is_the_closed_form():
    # 2 zeta + F'(V_b) = 0, i.e. zeta_H(V_b) = -F'(V_b) / 2, over a range of V_b
    vbs = np.linspace(0.004, 0.03, 27)
    curve, _ = hopf_curve(MODEL, LAW, "vb", "zeta", vbs, np.linspace(0.0, 1.0, 201))
    assert sorted(p.x for p in curve.points) == pytest.approx(list(vbs))
    for p in curve.points:
        assert p.y == pytest.approx(-stribeck_slope(p.x) / 2.0, rel=1e-12, abs=1e-15)


def test_hopf_criticality_and_the_bautin_point_match_the_closed_form():
    # l1 = -F'''(V_b)/16 and F''' ~ (-8 r^3 + 12 r) e^{-r^2} (r = V_b/V_s): the criticality changes at r^2 = 3/2
    vbs = np.linspace(0.004, 0.03, 14)
    curve, bautin = hopf_curve(MODEL, LAW, "vb", "zeta", vbs, np.linspace(0.0, 1.0, 201))
    for p in curve.points:
        r = p.x / VS
        assert p.detail["criticality"] == ("supercritical" if -8 * r**3 + 12 * r > 0 else "subcritical")
    (b,) = bautin
    assert b.x == pytest.approx(math.sqrt(1.5) * VS, abs=1e-10)
    assert b.y == pytest.approx(-stribeck_slope(b.x) / 2.0, rel=1e-9)


def test_hopf_criticality_agrees_with_the_continuation():
    # the side the cycles appear on (the continuation's own test) agrees with the sign of l1
    for vb in (0.010, 0.016):
        m = BeltOscillator(zeta=0.3, vb=vb)
        res = continuation(m, LAW, "zeta", 0.05, 0.95, seeds=("hopf",), n_equilibria=41)
        hopf = next(b for b in res.bifurcations if b.type == "hopf")
        curve, _ = hopf_curve(m, LAW, "vb", "zeta", [vb], np.linspace(0.05, 0.95, 181))
        assert curve.points[0].y == pytest.approx(hopf.value, rel=1e-12)
        assert curve.points[0].detail["criticality"] == hopf.detail["criticality"]


def _sticks_for_good(vb, zeta):
    traj = simulate(BeltOscillator(zeta=zeta, vb=vb), Coulomb(FD, FS), Exact(), t_end=400.0)
    return bool(np.any(traj.mode[-len(traj.mode) // 4:] == 0))


def test_coulomb_grazing_curve_matches_bisection_on_brute_force_simulations():
    law = Coulomb(FD, FS)
    zetas = np.array([0.01, 0.03, 0.06])
    curve = grazing_curve(BeltOscillator(zeta=0.05, vb=0.01), law, "zeta", "vb", zetas, np.linspace(0.001, 0.2, 200))
    assert [p.x for p in curve.points] == pytest.approx(list(zetas))
    for p in curve.points:
        lo, hi = 0.001, 0.2
        for _ in range(22):
            mid = 0.5 * (lo + hi)
            if _sticks_for_good(mid, p.x):
                lo = mid
            else:
                hi = mid
        assert p.y == pytest.approx(0.5 * (lo + hi), abs=2e-7)
        assert p.detail["stick_slip_below"]


@pytest.fixture(scope="module")
def chart():
    return stability_chart(MODEL, LAW, "vb", np.linspace(0.004, 0.03, 14), "zeta", (0.0, 1.0), fold_every=1)


def test_fold_curve_points_are_the_folds_of_one_parameter_runs(chart):
    fold = chart.curve("fold")
    assert len(fold.points) >= 4
    for p in fold.points[::2]:
        m = BeltOscillator(zeta=0.3, vb=p.x)
        res = continuation(m, LAW, "zeta", max(0.0, p.y - 0.05), min(1.0, p.y + 0.05), seeds=("hopf", "start", "stop"))
        folds = [b.value for b in res.bifurcations if b.type == "fold" and b.detail.get("smooth")]
        if folds:  # the one-parameter run may see only the corner when fold and grazing are close
            assert min(abs(f - p.y) for f in folds) < 1e-9


def test_the_fold_grazing_point_lies_on_the_grazing_curve(chart):
    (fg,) = [p for p in chart.codim2 if p.kind == "fold_grazing"]
    assert fg.detail["located"]
    m, law = with_param(*with_param(MODEL, LAW, "vb", fg.x), "zeta", fg.y)
    g, dg = stick_slip_margin(m, law, "zeta")
    assert abs(g / dg) < 1e-9  # the grazing curve passes through it, to 1e-9 in zeta
    # and it lies between the last real fold and the first fold at a grazing corner
    fold_x = max(p.x for p in chart.curve("fold").points)
    assert fold_x < fg.x < fold_x + (chart.x_values[1] - chart.x_values[0])


def test_chart_to_dict_and_dataset(chart):
    import json

    json.dumps(chart.to_dict(), allow_nan=False)
    ds = chart.to_xarray()
    hopf = ds["hopf_zeta"].values[:, 0]
    assert hopf == pytest.approx([-stribeck_slope(v) / 2 for v in ds["vb"].values], rel=1e-12)


STATEFUL = [n for n in law_names() if law_class(n).internal_names]


def test_every_law_with_an_internal_state_is_named_here():
    assert {"lugre", "dahl", "elastoplastic", "rate_state"} <= set(STATEFUL)


@pytest.mark.parametrize("name", STATEFUL)
def test_a_chart_refuses_a_law_with_an_internal_state_before_any_work(name, tmp_path):
    """The chart's Hopf curve is 2 zeta + F'(V_b) = 0 on the slip curve of (X, X'): for LuGre at vb 0.05 it gave
    zeta 1.4715 where the whole state's Hopf point (continue, the guide) is 1.23629.  The map refuses such a law,
    before the sweep under the curves writes anything."""
    law = law_class(name)()
    store = tmp_path / "under.nc"
    for call in (lambda: stability_chart(MODEL, law, "vb", [0.04, 0.05], "zeta", (0.0, 2.0)),
                 lambda: stability_map(MODEL, law, "vb", [0.04, 0.05], "zeta", (0.0, 2.0), sweep_shape=(2, 2),
                                       sweep_out=store)):
        with pytest.raises(ValueError, match=f"internal state; {name} has"):
            call()
    assert not store.exists()
    assert main(["map", "--friction", name, "--x", "vb=0.04:0.05:2", "--y", "zeta=0:2", "--json"]) == 2


def test_a_fold_curve_followed_in_x_does_not_land_on_the_hopf_point():
    """At a Hopf point the vanishing cycle solves the fold's equations (P = X, P' = 1) too: the fold curve followed
    from V_b = 0.016 to 0.018 landed there (zeta 0.14099, X = X*), beside the real fold (0.28439).  A fold whose cycle
    has no amplitude is refused, and the chart's folds are each a cycle's."""
    chart = stability_chart(MODEL, LAW, "vb", [0.014, 0.016, 0.018], "zeta", (0.0, 1.0))
    curves = {c.kind: c.points for c in chart.curves}
    hopf = {p.x: p.y for p in curves["hopf"]}
    assert len(curves["fold"]) == 3 and sorted({p.x for p in curves["fold"]}) == [0.014, 0.016, 0.018]
    for p in curves["fold"]:
        assert p.y > hopf[p.x] + 0.01  # beyond the Hopf point, where the subcritical family turns
    assert not curves["fold_at_grazing"]


def test_a_map_without_a_sweep_store_leaves_no_temporary_files(tmp_path, monkeypatch):
    """Without sweep_out the sweep under the map went to a fresh ff_map_* directory that nothing removed: one
    sweep.nc left in the temporary directory per map.  The store now lives only as long as the run."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    chart = stability_map(BeltOscillator(zeta=0.1, vb=0.1), Coulomb(0.3, 0.4), "vb", [0.1, 0.2], "zeta", (0.0, 0.2),
                          sweep_shape=(2, 2), t_end=40.0)
    assert chart.heat == "R_c" and chart.sweep["R_c"].shape == (2, 2) and np.isfinite(chart.sweep["R_c"].values).any()
    assert list(tmp_path.iterdir()) == []
