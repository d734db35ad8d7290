"""A model sweep's chunk runs its points on threads: every swept value is the point's own run and analysis, bitwise."""

from __future__ import annotations

import math

import tomllib

import numpy as np
import pytest

from frictionflow.analysis.structure import STRUCTURE_KINDS, analyze_structure
from frictionflow.core import threads
from frictionflow.solvers.structure import simulate_system, structure_solvers
from frictionflow.sweep.model import compute_model_chunk, parse_model_sweep
from frictionflow.system import System

from .test_structure_sweep import TWO

#: the two-mass chain of the sweep tests with a harmonic force on x2
FORCED = TWO + "\n[[force]]\non = { x2 = 1.0 }\namplitude = 0.02\nomega = 0.7\n"
BELTS, AMPLITUDES, T_END = [0.005, 0.02], [0.0, 0.02], 100.0


@pytest.fixture(scope="module")
def cfg():
    system = System.from_dict(tomllib.loads(FORCED), source=None)
    return parse_model_sweep({"t_end": T_END, "grid": {"contact.0.belt": BELTS, "force.0.amplitude": AMPLITUDES}},
                             system)


def test_the_grid_holds_a_stick_slip_chain_and_forced_points(cfg):
    """One contact stuck while the other slips at some sample of some point; forced points among them."""
    mixed = []
    for index in np.ndindex(*cfg.shape):
        modes = simulate_system(cfg.point_system(index), T_END).modes
        mixed.append(bool(np.any((modes == 0).any(axis=0) & (modes != 0).any(axis=0))))
    assert any(mixed)
    assert cfg.point_system((0, 1)).entry("force.0.amplitude") > 0.0


def alone(system: System, solver: str = "exact") -> dict:
    """One point run and analysed on its own: the sweep's variables by name."""
    a = analyze_structure(simulate_system(system, T_END, solver=solver))
    ss = a.steady_state
    elements = (*system.spring_names, *system.damper_names, *system.force_names)
    return {"kind": STRUCTURE_KINDS.index(ss.kind), "solver": structure_solvers().index(solver), "period": ss.period, "stick_fraction": list(ss.stick_fraction),
            "P": [a.elements[e]["P"] for e in elements],
            "P_belt": [a.elements[c]["P_belt"] for c in system.contact_names],
            "P_heat": [a.elements[c]["P_heat"] for c in system.contact_names],
            "X_max": [a.amplitude["X_max"][d] for d in system.dof], "X_min": [a.amplitude["X_min"][d] for d in system.dof],
            "energy_residual": a.energy_residual,
            "t_lost": [a.motion.lost[1] if a.motion.lost is not None and a.motion.lost[0] == c else math.nan
                       for c in system.contact_names]}


@pytest.mark.parametrize("n_threads", [1, 3])
def test_a_threaded_chunk_equals_each_point_run_alone(cfg, monkeypatch, n_threads):
    """The whole grid as one chunk, its points spread over ``n_threads`` threads (more threads than cores is
    allowed: the pieces interleave), against each point run and analysed on its own, one after the other."""
    monkeypatch.setattr(threads.numba, "get_num_threads", lambda: n_threads)
    got = compute_model_chunk(cfg.source, (0, 0), cfg.shape)
    names = [v.name for v in cfg.variables]
    assert names == ["kind", "solver", "period", "stick_fraction", "P", "P_belt", "P_heat", "X_max", "X_min", "energy_residual",
                     "t_lost"]
    for index in np.ndindex(*cfg.shape):
        want = alone(cfg.point_system(index))
        for name, arr in zip(names, got):
            np.testing.assert_array_equal(arr[index], want[name], err_msg=f"{name} at {index}")


def test_a_threaded_chunk_of_a_stribeck_model_equals_each_point_run_alone(monkeypatch):
    """The adaptive solver's points (a Stribeck contact) on three threads, bitwise as each run alone (its kernel
    releases the GIL as the exact one's does).  Two points, each about 3 s of Lyapunov runs: both run at once."""
    stribeck = FORCED.replace('friction = "coulomb"', 'friction = "stribeck"\nvs = 0.005')
    system = System.from_dict(tomllib.loads(stribeck), source=None)
    cfg = parse_model_sweep({"t_end": T_END, "grid": {"contact.0.belt": BELTS[:1], "force.0.amplitude": AMPLITUDES}},
                            system)
    assert cfg.solver == "adaptive"
    monkeypatch.setattr(threads.numba, "get_num_threads", lambda: 3)
    got = compute_model_chunk(cfg.source, (0, 0), cfg.shape)
    for index in np.ndindex(*cfg.shape):
        want = alone(cfg.point_system(index), "adaptive")
        for v, arr in zip(cfg.variables, got):
            np.testing.assert_array_equal(arr[index], want[v.name], err_msg=f"{v.name} at {index}")
