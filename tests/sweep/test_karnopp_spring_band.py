"""Karnopp's band under the spring rule, through the batched exact kernel (sweeps, basins) and simulate.

Inside the band the spring rule holds X against the spring alone, so the damper still brakes X' to 0:
X'' = -2 zeta X', and a final band phase comes to rest at X + X'/(2 zeta), not where it entered the band.  The
batched kernel stopped there and reported the entry point (X = F_s = 0.02 from the default start), 1-59 % off
simulate's X, sometimes with another kind; the sweep and basins now run such a phase on and judge its samples
as simulate does.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.basins import basins
from frictionflow.friction import Karnopp
from frictionflow.quantities import KINDS
from frictionflow.solvers import Exact
from frictionflow.sweep.compute import VARIABLES, compute_chunk

FD = 0.02
SETTINGS = {"friction": "karnopp", "fd": FD, "t_end": 300.0, "stick_force": "spring"}
GRID = {"zeta": [0.02, 0.05, 0.2], "vb": [0.0002, 0.0005, 0.0009]}  # V_b < V_d = 0.001: the start is in the band


def _simulated(zeta: float, vb: float, t_end: float = 300.0, x0: float = FD, v0: float | None = None) -> dict:
    law = Karnopp(FD, FD, stick_force="spring")
    tr = simulate(BeltOscillator(zeta=zeta, vb=vb), law, Exact(), t_end=t_end, x0=x0, v0=vb if v0 is None else v0)
    return analyze(tr).quantities()


def test_the_sweep_equals_simulate_in_the_band() -> None:
    out = compute_chunk({"settings": SETTINGS, "grid": GRID}, (0, 0), (3, 3))
    kinds = set()
    for (i, zeta), (j, vb) in ((a, b) for a in enumerate(GRID["zeta"]) for b in enumerate(GRID["vb"])):
        want = _simulated(zeta, vb)
        kinds.add(KINDS[int(want["kind"])])
        for q, (name, _, _) in enumerate(VARIABLES):
            got, ref = float(out[q, i, j]), want[name]
            if math.isnan(ref):
                assert math.isnan(got), (zeta, vb, name)
            else:
                assert got == pytest.approx(ref, rel=1e-12, abs=1e-15), (zeta, vb, name, got, ref)
    assert "equilibrium" in kinds


def test_simulate_rests_where_the_damper_brakes_the_band_to() -> None:
    """From X = F_s with X' = V_b the force saturates (X'' = -X - 2 zeta X' + F_s) for half a damped swing, which
    returns X' = -V_b exp(-zeta pi / omega_d) into the band; then X'' = -2 zeta X' rests it at X + X'/(2 zeta)."""
    zeta, vb = 0.05, 0.0005
    rest = FD - vb * math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)) / (2 * zeta)
    q = _simulated(zeta, vb, t_end=1000.0)
    assert KINDS[int(q["kind"])] == "equilibrium"
    assert q["X_max"] == pytest.approx(rest, abs=1e-12) and q["X_min"] == pytest.approx(rest, abs=1e-12)


def test_basins_equal_simulate_in_the_band() -> None:
    zeta, vb = 0.05, 0.0005
    b = basins(SETTINGS, zeta=zeta, vb=vb, x0=(0.02, 0.03, 2), v0=(0.0005, 0.001, 2))
    got = b.dataset["X_max"].values
    for i, x0 in enumerate(b.dataset["x0"].values):
        for j, v0 in enumerate(b.dataset["v0"].values):
            assert got[i, j] == pytest.approx(_simulated(zeta, vb, x0=float(x0), v0=float(v0))["X_max"], rel=1e-12)
    assert np.all(got < FD)  # every start comes to rest below where the spring alone is held
