"""The brute-force sweep lands on the stable orbits that shooting finds."""

from __future__ import annotations

import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.orbits import find_orbit, sweep, with_param


def test_sweep_amplitudes_are_the_stable_orbits():
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04)
    rows = sweep(model, law, "vb", [0.005, 0.01, 0.02], t_end=300.0)
    for row in rows:
        orbit = find_orbit(*with_param(model, law, "vb", row["value"]), transient=0.0, x0=0.05, v0=0.0)
        assert row["kind"] == "periodic"
        assert row["amplitude"] == pytest.approx(orbit.amplitude, rel=1e-9)
        assert row["period"] == pytest.approx(orbit.period, rel=1e-9)
        assert row["P_fin"] == pytest.approx(orbit.measures.power.P_fin, rel=1e-9)
        assert row["TR_B"] == pytest.approx(orbit.measures.TR_B, rel=1e-9)
