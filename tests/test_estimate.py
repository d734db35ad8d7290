"""The estimate record (:mod:`frictionflow.estimate`), the one comparison with the limits, and the solvers' cost
models against the runs they estimate (steps counted by the runs themselves, not timed)."""

from __future__ import annotations

import io
import math
import warnings
from collections import namedtuple

import pytest
from rich.console import Console

from frictionflow import BeltOscillator, simulate
from frictionflow import _progress, estimate
from frictionflow.estimate import GIB, Estimate, Limits, enforce, limited, located_run, refusal
from frictionflow.friction import law_class
from frictionflow.solvers import RK4, Adaptive, Exact

HOUR = 3600.0


def test_the_record_adds_repeats_and_writes():
    a = Estimate(1e6, "RK4 steps", 10.0, memory=GIB)
    b = Estimate(5.0, "orbit flows", 20.0, memory=2 * GIB, outputs=(("out", "x.nc", 3.0),))
    both = a.then(b)
    assert (both.work, both.unit, both.seconds, both.memory, both.outputs) == (1e6, "RK4 steps", 30.0, 2 * GIB,
                                                                              (("out", "x.nc", 3.0),))
    many = a.times(4, "per point")
    assert (many.work, many.seconds, many.memory, many.unit) == (4e6, 40.0, GIB, "RK4 steps per point")
    assert a.writing(None, 1e9) is a and a.writing("o.zarr", 2.0, "--out").outputs == (("--out", "o.zarr", 2.0),)
    assert Estimate(1, "x", 7200.0, cores=4).wall == 1800.0


def test_the_text_says_the_work_its_time_and_what_is_large():
    outputs = (("out", "/data/r.zarr", 2.0**41), ("plot", "s.nc", 10.0))
    text = Estimate(5e10, "RK4 steps", 2 * 86400.0, memory=3 * GIB, outputs=outputs).text()
    assert text == "5e+10 RK4 steps, about 2 days, 3 GiB in memory, r.zarr 2 TiB"
    assert Estimate(10, "points", 90.0, cores=2).text() == "10 points, about 45 s on 2 cores"
    assert estimate.duration(5400.0) == "1.5 h" and estimate.duration(400 * 86400.0) == "1.1 years"


def test_the_limits_refuse_time_then_say_how_to_lift_them():
    lim = Limits(lift="--no-limit")
    assert refusal(Estimate(1, "x", 0.9 * HOUR), lim) is None
    why = refusal(Estimate(1, "x", 2 * HOUR), lim)
    assert why.startswith("estimated 1 x, about 2 h") and "above the limit of 1 h" in why and "--no-limit" in why
    assert refusal(Estimate(1, "x", 2 * HOUR, cores=4), lim) is None  # half an hour on four cores
    assert refusal(Estimate(1, "x", math.nan), lim) is not None  # an unknowable cost is not within the limit


def test_the_limits_refuse_an_output_above_its_disks_free_space(tmp_path, monkeypatch):
    Usage = namedtuple("Usage", "total used free")
    asked = []
    monkeypatch.setattr(estimate.shutil, "disk_usage", lambda p: asked.append(p) or Usage(100, 0, 50))
    target = tmp_path / "new" / "deeper" / "out.zarr"  # not there yet: its nearest existing ancestor's disk
    why = refusal(Estimate(1, "x", 1.0).writing(target, 51, "--out"), Limits(lift="--no-limit"))
    assert why.startswith(f"--out: {str(target)!r} would need about 51 B but its disk has 50 B free: no space left")
    assert "(estimated 1 x, about 1 s)" in why and why.endswith("--no-limit")
    assert asked == [tmp_path]
    assert refusal(Estimate(1, "x", 1.0).writing(target, 50), Limits()) is None
    assert refusal(Estimate(1, "x", 1.0).writing(target, 51), Limits(disk=False)) is None


def test_the_limits_refuse_memory_above_max_memory():
    why = refusal(Estimate(1, "x", 1.0, memory=8 * GIB), Limits(memory=4.0))
    assert "needs 8 GiB in memory but max_memory=4 GiB" in why


def test_enforce_compares_only_inside_limits_and_only_the_first_estimate():
    huge = Estimate(1, "x", 1e9)
    enforce(huge)  # no limits in force: the API runs what it is asked
    with limited(Limits()):
        with pytest.raises(ValueError, match="above the limit of 1 h"):
            enforce(huge)
        enforce(Estimate(2, "y", 1.0))
        assert _progress.ESTIMATE.get() == "2 y, about 1 s"
        enforce(huge)  # a run of the accepted work: covered by its estimate
    assert _progress.ESTIMATE.get() is None
    with limited(None):  # lifted: nothing refused, the estimate still shown
        enforce(huge)
        assert _progress.ESTIMATE.get().startswith("1 x, about 31.7 years")


def test_the_progress_bar_shows_the_estimate(monkeypatch):
    screen = io.StringIO()
    monkeypatch.setattr(_progress, "Console", lambda stderr: Console(file=screen, width=200, force_terminal=False))
    with limited(None):
        enforce(Estimate(3e6, "RK4 steps", 120.0))
        with _progress.progress_bar("rk4", 10) as advance:
            advance(10)
    assert "rk4 (estimated 3e+06 RK4 steps, about 2 min)" in screen.getvalue()


def test_located_runs_bound_their_switches_by_the_time_and_the_forcing():
    slow, fast = located_run(100, 2 * math.pi * 1e3, "map_step"), located_run(100, 2 * math.pi * 1e3, "map_step", omega=3.0)
    assert "up to 4e+03 switches" in slow.unit and "up to 1.2e+04 switches" in fast.unit
    assert fast.seconds > slow.seconds > 100 * estimate.SECONDS_PER["map_step"]


# -- the solvers' cost models against their runs ---------------------------------------------------

@pytest.mark.filterwarnings("ignore::frictionflow.solvers.base.CoarseStepWarning")
def test_rk4_counts_its_steps_exactly():
    model, law = BeltOscillator(0.05, 0.01, fex=0.3, omega=3.0), law_class("coulomb")(0.02, 0.04)
    solver = RK4()
    traj = simulate(model, law, solver, t_end=300.0)
    assert solver.step_estimate(300.0, model, law) == traj.solver["steps"]
    assert solver.cost(model, law, 300.0).work == traj.solver["steps"]


@pytest.mark.parametrize("solver", [Exact(), Adaptive()], ids=["exact", "adaptive"])
@pytest.mark.parametrize("forced", [False, True], ids=["unforced", "forced"])
def test_event_driven_solvers_take_fewer_steps_than_estimated(solver, forced):
    model = BeltOscillator(0.05, 0.01, fex=0.3 if forced else 0.0, omega=3.0)
    law = law_class("coulomb")(0.02, 0.04)
    traj = simulate(model, law, solver, t_end=300.0)
    assert len(traj.t) <= solver.step_estimate(300.0, model, law) <= 40 * len(traj.t)


@pytest.mark.parametrize("zeta", [50.0, 500.0])
def test_adaptive_counts_the_steps_a_stiff_damping_forces(zeta):
    """Dormand-Prince's stability limit h |lambda| < 3.3 sets the steps of a strongly damped run (not its accuracy)."""
    model, law = BeltOscillator(zeta, 0.01), law_class("stribeck")()
    solver = Adaptive()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traj = simulate(model, law, solver, t_end=100.0)
    assert len(traj.t) <= solver.step_estimate(100.0, model, law) <= 10 * len(traj.t)


def test_a_slip_curve_below_the_normal_floats_takes_adaptive_runs_to_their_cap():
    stribeck = law_class("stribeck")
    assert stribeck(vs=1e-100).resolvable() and not stribeck(vs=1e-300).resolvable()
    assert not stribeck(vs=1e-160).resolvable()  # 1e-320 is subnormal
    assert law_class("coulomb")(0.02).resolvable()
    model, solver = BeltOscillator(0.05, 0.01), Adaptive(max_steps=12345)
    assert solver.step_estimate(1.0, model, stribeck(vs=1e-300)) == 12345
