"""Sweeps over a moving belt's axes: one solver per sweep, and each point what ``simulate`` gives with it.

``solver = auto`` picks per run: for Karnopp exact on a belt at constant speed and RK4 on a moving one, whose
results differ by more than rounding (periods 0.5% apart at the point below). A sweep runs one solver, so a grid
where auto would pick both is refused; with an explicit solver every point is ``analyze(simulate(...))`` with it.
"""

from __future__ import annotations

import warnings

import pytest

from frictionflow import RK4, BeltOscillator, Karnopp, simulate
from frictionflow.cli import main
from frictionflow.sweep import parse_sweep, run_sweep

from ..cli.processes import one_line
from .test_sweep import same_as_simulate

KARNOPP = {"t_end": 50.0, "zeta": 0.02, "fs": 0.04, "vb": 0.01}
REFUSED = 'solver = auto picks exact where grid.vb_amplitude = 0 and rk4 where it is > 0, and a sweep runs one ' \
          'solver; set solver explicitly (solver = "rk4" runs every point)'


def test_auto_over_a_still_and_a_moving_belt_is_refused_and_the_solver_named_agrees_with_simulate(tmp_path, capsys):
    grid = {"vb_amplitude": [0.0, 0.005], "vb_omega": [0.5, 1.5]}
    with pytest.raises(ValueError) as e:
        parse_sweep({**KARNOPP, "grid": grid})
    assert str(e.value) == f"config: {REFUSED}"
    config = tmp_path / "s.toml"
    config.write_text("t_end = 50.0\nzeta = 0.02\nfs = 0.04\nvb = 0.01\n[grid]\nvb_amplitude = [0.0, 0.005]\n"
                      "vb_omega = [0.5, 1.5]\n")
    assert main(["sweep", str(config), "--out", str(tmp_path / "r.nc")]) == 2
    one_line(capsys.readouterr().err, f"{config}: {REFUSED}")
    assert list(tmp_path.iterdir()) == [config]  # refused before anything was written
    # the advice taken: every point, the still belt's too, is analyze(simulate(...)) with that solver
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (RK4's thinning notice: the same in both)
        ds = run_sweep({**KARNOPP, "solver": "rk4", "grid": grid}, tmp_path / "s.zarr").load()
        for amp in (0.0, 0.005):
            model = BeltOscillator(zeta=0.02, vb=0.01, vb_amplitude=amp, vb_omega=1.5)
            same_as_simulate(ds, {"vb_amplitude": amp, "vb_omega": 1.5}, model, Karnopp(0.02, 0.04), RK4(), t_end=50.0,
                             rtol=0.0)


def test_auto_over_a_belt_that_moves_at_every_point_runs_what_simulate_picks_there(tmp_path):
    """Another axis beside the amplitude: its extremes were checked with auto's pick for a belt standing still
    (exact), which has no step to check (AttributeError)."""
    spec = {**KARNOPP, "grid": {"vb_amplitude": [0.003, 0.005], "vb_omega": [0.5, 1.5]}}
    assert parse_sweep(spec).run.solver == "rk4"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = run_sweep(spec, tmp_path / "s.zarr").load()
        model = BeltOscillator(zeta=0.02, vb=0.01, vb_amplitude=0.005, vb_omega=0.5)
        assert simulate(model, Karnopp(0.02, 0.04), t_end=1.0).solver["name"] == "rk4"
        same_as_simulate(ds, {"vb_amplitude": 0.005, "vb_omega": 0.5}, model, Karnopp(0.02, 0.04), t_end=50.0, rtol=0.0)
