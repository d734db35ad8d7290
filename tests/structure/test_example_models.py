"""The shipped model files do what docs/guide/models.md says of them (its snippets use them)."""

from __future__ import annotations

from pathlib import Path

import pytest

from frictionflow.analysis.structure import analyze_structure
from frictionflow.orbits import find_structure_orbit
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import load_system

MODELS = Path(__file__).resolve().parents[2] / "examples" / "models"


def test_every_example_model_loads():
    files = sorted(MODELS.glob("*.toml"))
    assert {f.name for f in files} >= {"two_mass_chain.toml", "stick_slip_chain.toml", "stribeck_chain.toml",
                                      "hoffmann_2dof.toml"}
    for f in files:
        load_system(f)


def test_the_stick_slip_chain_is_one_periodic_cycle_through_simulate_and_the_orbit():
    chain = load_system(MODELS / "stick_slip_chain.toml")
    ss = analyze_structure(simulate_system(chain, 1000.0)).steady_state
    assert ss.kind == "periodic"
    orbit = find_structure_orbit(chain, t_transient=300.0)
    assert orbit.stable
    assert orbit.period == pytest.approx(ss.period, rel=1e-9)
    assert orbit.stick_fraction == pytest.approx(ss.stick_fraction, abs=1e-9)
    assert round(orbit.period, 4) == 7.2224  # the guide's number


def test_the_stribeck_chain_is_periodic_on_the_adaptive_solver():
    ss = analyze_structure(simulate_system(load_system(MODELS / "stribeck_chain.toml"), 1000.0, solver="adaptive"))
    assert ss.steady_state.kind == "periodic"


def test_the_two_mass_chain_slides_steadily():
    ss = analyze_structure(simulate_system(load_system(MODELS / "two_mass_chain.toml"), 300.0)).steady_state
    assert ss.kind == "equilibrium"
