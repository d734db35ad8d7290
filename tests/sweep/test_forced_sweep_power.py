"""A forced sweep stores the external force's input P_ex, so each point's power balance closes from the dataset.

Sweeps stored P_dv, P_df and P_fin but not P_ex (simulate --json and response report it): a forced point's
balance P_dv + P_df = P_fin + P_ex (over whole periods, K + U back where it was) could not be checked from the
output.  Unforced sweeps store P_ex = 0.
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.friction import Coulomb
from frictionflow.quantities import KINDS
from frictionflow.solvers import Exact
from frictionflow.sweep import run_sweep

SETTINGS = {"friction": "coulomb", "fd": 0.05, "fs": 0.05, "vb": 0.0, "zeta": 0.05, "t_end": 300.0}


@pytest.fixture(scope="module")
def forced(tmp_path_factory):
    spec = {**SETTINGS, "grid": {"fex": [0.1, 0.3], "omega": [0.6, 0.8, 1.3]}}
    return run_sweep(spec, tmp_path_factory.mktemp("s") / "f.nc").load()


def test_the_balance_closes_from_the_dataset(forced) -> None:
    periodic = forced["kind"].values == KINDS.index("periodic")
    assert periodic.sum() >= 4
    p = {k: forced[k].values[periodic] for k in ("P_dv", "P_df", "P_fin", "P_ex")}
    assert np.all(p["P_ex"] > 0)  # the force feeds the motion on a surface at rest
    gap = np.abs(p["P_dv"] + p["P_df"] - p["P_fin"] - p["P_ex"]) / p["P_ex"]
    assert gap.max() < 1e-9
    assert forced["P_ex"].attrs["long_name"].startswith("time-averaged power put in by the external force")


def test_p_ex_equals_simulate(forced) -> None:
    model = BeltOscillator(zeta=0.05, vb=0.0, fex=0.3, omega=0.8)
    q = analyze(simulate(model, Coulomb(0.05, 0.05), Exact(), t_end=300.0, x0=0.05, v0=0.0)).quantities()
    assert float(forced["P_ex"].sel(fex=0.3, omega=0.8)) == pytest.approx(q["P_ex"], rel=1e-12)
    assert q["P_ex"] == pytest.approx(0.0381135, rel=1e-6)  # the QA's simulate --json at this point


def test_an_unforced_sweep_stores_zero(tmp_path) -> None:
    settings = {k: v for k, v in SETTINGS.items() if k != "zeta"}
    ds = run_sweep({**settings, "vb": 0.01, "fs": 0.1, "grid": {"zeta": [0.0, 0.1]}}, tmp_path / "u.nc").load()
    assert np.all(ds["P_ex"].values == 0.0)
