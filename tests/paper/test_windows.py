"""Averaging over whole cycles: against closed-form quadrature, the energy balance and power_flow."""

import numpy as np
import pytest

from frictionflow import power_flow
from frictionflow.paper.runs import Point, run
from frictionflow.paper.windows import Cycles, tail

from .closed_form import slip_averages

CASE2 = Point(0.01, 0.01, 0.02)


@pytest.fixture(scope="module")
def case2_runs(settings):
    return {s: run(CASE2, s, settings) for s in ("rk4", "exact")}


@pytest.mark.parametrize(("solver", "rtol"), [("exact", 1e-4), ("rk4", 1e-3)])
def test_last_cycle_averages_match_quadrature_of_the_closed_form(case2_runs, solver, rtol):
    # the free spiral from the exact solver's last switch, integrated by scipy's adaptive quadrature
    ex = case2_runs["exact"]
    k = int(np.searchsorted(ex.t, ex.extra["t_terminal"]))
    start = (float(ex.t[k]), float(ex.x[k]), float(ex.v[k]))
    cycles = Cycles(case2_runs[solver])
    w = cycles.average(*cycles.last_cycle())
    ref = slip_averages(w.t0, w.t1, start, CASE2.fd, CASE2.zeta)
    assert 590 < w.t0 < w.t1 <= 600
    for name in ("P_dv", "P_fin", "P_df"):
        assert getattr(w, name) == pytest.approx(ref[name], rel=rtol), name


def test_every_cycle_of_the_free_spiral_balances_energy(case2_runs):
    # P_fin - P_df - P_dv is the mean rate of change of K + U, taken from the endpoint states alone.
    # (The first cycle, which visits the band, has F_c jumping between samples: not a smooth quadrature.)
    traj = case2_runs["rk4"]
    cycles = Cycles(traj)
    s = cycles.starts("min")
    a = cycles.averages(s[traj.t[s] > 10.0])
    resid = a["P_fin"] - a["P_df"] - a["P_dv"] - a["dE"]
    assert len(resid) > 80
    assert np.all(np.abs(resid) < 1e-6 * a["P_fin"])


def test_vectorised_cycles_equal_one_window_at_a_time(case2_runs):
    cycles = Cycles(case2_runs["exact"])
    s = cycles.starts("max")[-6:]
    many = cycles.averages(s)
    for k in range(len(s) - 1):
        one = cycles.average(int(s[k]), int(s[k + 1]))
        assert one.P_fin == many["P_fin"][k] and one.TR_B == many["TR_B"][k]


def test_window_quadrature_agrees_with_the_solvers_work_integrals_where_those_are_precise(settings):
    # Case I: the running integrals grow linearly, their difference over a late cycle keeps ~10 digits
    traj = run(Point(0.0, 0.01, 0.02), "rk4", settings)
    cycles = Cycles(traj)
    i0, i1 = cycles.last_cycle()
    w = cycles.average(i0, i1)
    pf = power_flow(traj, (traj.t[i0], traj.t[i1]))
    assert w.P_fin == pytest.approx(pf.P_fin, rel=1e-6)
    assert w.P_df == pytest.approx(pf.P_df, rel=1e-6)


def test_tail_gives_the_same_last_cycle(case2_runs):
    traj = case2_runs["rk4"]
    whole, end = Cycles(traj), Cycles(tail(traj, 550.0))
    a = whole.average(*whole.last_cycle())
    b = end.average(*end.last_cycle())
    assert (a.t0, a.t1, a.P_dv, a.R_c) == (b.t0, b.t1, b.P_dv, b.R_c)


def test_cycle_starts_are_maxima_and_minima_of_x(case2_runs):
    traj = case2_runs["exact"]
    cycles = Cycles(traj)
    hi, lo = cycles.starts("max")[-3:], cycles.starts("min")[-3:]
    assert np.all(traj.x[hi] > 0.02) and np.all(traj.x[lo] < 0.02)
    with pytest.raises(ValueError, match=r"^at must be one of max, min"):
        cycles.starts("zero")
