"""A sweep point's extremes of X are simulate's: both take them from the section records.

The batched kernels keep no samples: X_max and X_min are the records' values at the turns of X (cubic Hermite
between the steps).  ``analyze`` took the largest and smallest sample instead; on a fixed step they differ by
O(dt^2): 3e-6 of X_max at dt = 0.005 (a QA report), beyond the 1e-6 the paths agree to.
"""

from __future__ import annotations

import warnings

import pytest

from frictionflow import BeltOscillator, Karnopp, RK4, analyze, simulate
from frictionflow.sweep import run_sweep


def test_an_rk4_sweep_point_has_simulates_extremes(tmp_path):
    cfg = {"solver": "rk4", "dt": 0.005, "t_end": 300.0, "fs": 0.04, "grid": {"zeta": [0.05], "vb": [0.01]}}
    row = run_sweep(cfg, tmp_path / "r.nc", progress=False).load().sel(zeta=0.05, vb=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse step's warning: this step is the point
        traj = simulate(BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04), RK4(dt=0.005), t_end=300.0)
    an = analyze(traj)
    assert an.steady_state.kind == "periodic"
    for name in ("X_max", "X_min", "V_max", "V_min"):
        assert float(row[name]) == pytest.approx(an.amplitude[name], rel=1e-12, abs=0.0), name
    # between samples: the turn's value lies beyond every sample of the window
    i0, i1 = traj.index(an.steady_state.window[0]), traj.index(an.steady_state.window[1])
    assert an.amplitude["X_max"] >= traj.x[i0:i1 + 1].max() and an.amplitude["X_min"] <= traj.x[i0:i1 + 1].min()
