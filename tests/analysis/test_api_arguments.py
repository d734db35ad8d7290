"""Out-of-range settings of the API's analysis and orbit functions are refused in one line naming them, as the command
line refuses the same values (they once ran: ``steady_state(rtol=2)`` called a stick-slip cycle an equilibrium,
``continuation(step=-1)`` ended its branch early, ``find_orbit(tol=-1)`` said no orbit exists,
``transmissibility`` of a reversed window failed inside numpy)."""

from __future__ import annotations

import math

import pytest

from frictionflow import BeltOscillator, Coulomb, Exact, Stribeck, analyze, simulate
from frictionflow import instantaneous_power, sliding_equilibrium
from frictionflow.analysis import lyapunov_exponents, power_flow, steady_state, transmissibility
from frictionflow.analysis.stability import steady_sliding
from frictionflow.analysis.structure import analyze_structure
from frictionflow.orbits import continuation, find_orbit
from frictionflow.orbits.settings import ContinuationSettings
from frictionflow.solvers.structure import simulate_system

MODEL, LAW = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04)


@pytest.fixture(scope="module")
def run():
    return simulate(MODEL, LAW, t_end=300.0)


@pytest.mark.parametrize("rtol", [math.nan, 2.0, -1.0, 0.0, "1e-6", True])
def test_a_classification_tolerance_out_of_range_is_refused(run, rtol):
    with pytest.raises(ValueError, match=r"^rtol must be a number in \(0, 1\), got"):
        steady_state(run, rtol=rtol)
    with pytest.raises(ValueError, match=r"^rtol must be"):
        analyze(run, rtol=rtol)


def test_the_same_run_with_a_good_tolerance_is_the_cycle(run):
    assert steady_state(run, rtol=1e-6).kind == "periodic" and steady_state(run, min_periods=3).kind == "periodic"
    with pytest.raises(ValueError, match=r"^min_periods must be an integer >= 1"):
        steady_state(run, min_periods=0)


@pytest.mark.parametrize("window", [(200.0, 100.0), (math.nan, 1.0), (0.0, 1000.0), ("a", "b"), (1.0,)])
def test_every_function_taking_a_window_checks_it_alike(run, window):
    for fn in (transmissibility, power_flow, lambda r, w: steady_state(r, window=w)):
        with pytest.raises(ValueError, match=r"^window must"):
            fn(run, window)


def test_a_window_inside_the_run_gives_the_averages_there(run):
    assert transmissibility(run, (100.0, 300.0)) == pytest.approx(analyze(run, window=(100.0, 300.0)).TR_B, rel=1e-15)


@pytest.mark.parametrize("kw, name", [({"tol": -1.0}, "tol"), ({"tol": math.nan}, "tol"), ({"returns": 1.5}, "returns"),
                                      ({"returns": 0}, "returns"), ({"max_iter": 0}, "max_iter"),
                                      ({"transient": -1.0}, "transient")])
def test_find_orbit_refuses_shooting_settings_out_of_range(kw, name):
    with pytest.raises(ValueError, match=f"^{name} must be"):
        find_orbit(MODEL, LAW, **kw)


@pytest.mark.parametrize("kw", [{"step": -1.0}, {"max_step": 0.0}, {"max_period": -1.0}, {"n_equilibria": -1},
                                {"n_equilibria": 2.5}, {"transient": math.nan}, {"sweep": -3}, {"max_points": 1}])
def test_continuation_refuses_settings_out_of_range_as_the_command_does(kw):
    [(name, _)] = kw.items()
    with pytest.raises(ValueError, match=f"^{name} must be"):
        continuation(MODEL, Stribeck(0.02, 0.04, vs=0.01), "zeta", 0.2, 0.4, **kw)
    with pytest.raises(ValueError, match=f"^{name} must be"):
        ContinuationSettings(**kw)


def test_simulate_takes_a_solver_by_name_as_the_solvers_guide_writes_it():
    """``solver="auto"`` (the guide's words) is the default solver, ``"exact"`` the exact one with its defaults; a
    wrong name or type is one line naming the argument (``"auto"`` failed with "'str' object has no attribute
    'supports'")."""
    want = simulate(MODEL, LAW, Exact(), t_end=50.0)
    for name in ("auto", "exact"):
        got = simulate(MODEL, LAW, name, t_end=50.0)
        assert got.solver["name"] == "exact" and (got.x == want.x).all() and (got.t == want.t).all()
    with pytest.raises(ValueError, match=r"^solver must be one of auto, exact"):
        simulate(MODEL, LAW, "exakt", t_end=50.0)
    with pytest.raises(TypeError, match=r"^solver must be a Solver"):
        simulate(MODEL, LAW, 3, t_end=50.0)


def test_a_wrong_object_is_a_type_error_naming_the_argument():
    """What the functions are given by mistake (a string for a run, a model or a system) is refused where they are
    called, naming the argument; these raised AttributeError from inside ('str' object has no attribute ...)."""
    calls = [(lambda: power_flow("x"), "traj"), (lambda: transmissibility("x"), "traj"),
             (lambda: steady_state("x"), "traj"), (lambda: instantaneous_power("x"), "traj"),
             (lambda: sliding_equilibrium("x", LAW), "model"), (lambda: sliding_equilibrium(MODEL, "x"), "friction"),
             (lambda: find_orbit("x", LAW), "model"), (lambda: lyapunov_exponents("x", LAW), "model"),
             (lambda: simulate_system("x", 10.0), "system"), (lambda: analyze_structure("x"), "motion"),
             (lambda: steady_sliding("x"), "assembly")]
    for call, name in calls:
        with pytest.raises(TypeError, match=f"^(steady_state: )?{name} must be"):
            call()
