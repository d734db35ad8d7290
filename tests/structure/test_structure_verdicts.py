"""A structure's run is an equilibrium only when it is one: not an undamped oscillation about steady sliding, not a
run too short for its unbalanced forces to show."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

import frictionflow as ff
from frictionflow.analysis.structure import analyze_structure, certified_sliding, structure_steady_state
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import System

HOFFMANN = Path(__file__).parents[2] / "examples" / "models" / "hoffmann_2dof.toml"
#: one mass from x = 0.5 at rest on a belt at 0.02: the spring force 0.5 is far above F_s = 0.04
ONE = {"dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}], "damper": [{"on": {"x": 1.0}, "c": 0.1}],
       "contact": [{"on": {"x": 1.0}, "belt": 0.02, "friction": "coulomb", "fd": 0.02, "fs": 0.04}],
       "initial": {"q": {"x": 0.5}}}


def _hoffmann(mu: float, damping: float = 0.0) -> System:
    model = tomllib.loads(HOFFMANN.read_text())
    model["contact"][0].update(fd=mu, fs=mu)
    if damping:
        model["damper"] = [{"on": {d: 1.0}, "c": damping} for d in model["dof"]]
    return System.from_dict(model, source=None)


def test_an_undamped_structure_below_flutter_keeps_oscillating_and_is_no_equilibrium():
    """Hoffmann's model at mu = 0.5 < mu_c = 0.625 (examples/models/hoffmann_2dof.toml): slipping for good, the
    motion is the linearisation's, x* + exp(A t)(x0 - x*), with A's roots +-i sqrt(2), +-i sqrt(1.5) from
    w^4 - (a + d) w^2 + a d - b (b + mu kH) = 0 (a = 1.5, b = -0.5, d = 2, kH = 1): a centre, nothing decays."""
    t_end = 300.0
    motion = simulate_system(_hoffmann(0.5), t_end)
    q_star = np.array([1.0 / 3.0, 1.0 / 12.0])  # K_eff q* = (mu P, 0), K_eff = [[1.5, 0], [-0.5, 2]]
    a = np.zeros((4, 4))
    a[:2, 2:] = np.eye(2)
    a[2:, :2] = -np.array([[1.5, 0.0], [-0.5, 2.0]])
    assert sorted(np.abs(np.linalg.eigvals(a).imag)) == pytest.approx([math.sqrt(1.5)] * 2 + [math.sqrt(2.0)] * 2)
    start = np.array([0.45, 0.11, 0.0, 0.0]) - np.concatenate((q_star, [0.0, 0.0]))
    times = np.linspace(t_end - 20.0, t_end, 201)
    closed = np.stack([np.concatenate((q_star, [0.0, 0.0])) + expm(a * t) @ start for t in times], axis=1)
    np.testing.assert_allclose(motion.states(times), closed, atol=1e-9)
    assert np.ptp(closed[0]) > 0.1  # x1 still swings over the last 20 time units
    assert not certified_sliding(motion)
    assert structure_steady_state(motion).kind == "quasi_periodic"  # sqrt(2 / 1.5) is irrational


def test_the_same_structure_damped_is_certified_to_slide_into_its_equilibrium():
    """With a damper on each dof (mu still below flutter for this damping) every root decays: the certificate
    holds and the analysis gives the equilibrium's own values."""
    motion = simulate_system(_hoffmann(0.5, damping=0.05), 300.0)
    assert certified_sliding(motion)
    a = analyze_structure(motion)
    assert a.steady_state.kind == "equilibrium"
    assert a.amplitude["X_max"]["x1"] == pytest.approx(1.0 / 3.0, rel=1e-12)


@pytest.mark.parametrize("t_end", [1e-9, 1e-6, 1e-3])
def test_a_run_too_short_to_move_is_not_settled_as_the_single_mass_says(t_end):
    """From x = 0.5 at rest the mass accelerates at about -0.48: after t_end its velocity is -0.48 t_end, a small
    number, but the state is no equilibrium (q'' is not 0).  The single-mass path says not settled too."""
    a = analyze_structure(simulate_system(System.from_dict(ONE, source=None), t_end))
    single = ff.analyze(ff.simulate(ff.BeltOscillator(zeta=0.05, vb=0.02), ff.Coulomb(0.02, 0.04), ff.Exact(),
                                    t_end=t_end, x0=0.5, v0=0.0))
    assert single.steady_state.kind == "not_settled"
    assert a.steady_state.kind == "not_settled"


@pytest.mark.parametrize("t_end", [1e-3, 1.0, 20.0])
def test_a_mass_stuck_at_rest_is_an_equilibrium_however_short_the_run(t_end):
    """Belt at rest, spring force 0.01 below F_s = 0.04: stuck for ever, nothing moves; the single mass agrees."""
    model = {**ONE, "contact": [{**ONE["contact"][0], "belt": 0.0}], "initial": {"q": {"x": 0.01}}}
    a = analyze_structure(simulate_system(System.from_dict(model, source=None), t_end))
    single = ff.analyze(ff.simulate(ff.BeltOscillator(zeta=0.05, vb=0.0), ff.Coulomb(0.02, 0.04), ff.Exact(),
                                    t_end=t_end, x0=0.01, v0=0.0))
    assert single.steady_state.kind == "equilibrium"
    assert a.steady_state.kind == "equilibrium"


def test_a_lasting_oscillation_on_a_fast_belt_is_periodic_not_an_equilibrium():
    """Undamped, 5e-4 off steady sliding x* = F_d = 0.1 on a belt at 1000: slipping for good, the motion is
    x* + 5e-4 cos t for ever (period 2 pi).  The at-rest test took the belt speed as the motion's scale, so its
    tolerance (1e-6 x 1000) swallowed the oscillation and said "equilibrium"; the single mass says periodic."""
    model = {"dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}],
             "contact": [{"on": {"x": 1.0}, "belt": 1000.0, "friction": "coulomb", "fd": 0.1, "fs": 0.2}],
             "initial": {"q": {"x": 0.1005}}}
    a = analyze_structure(simulate_system(System.from_dict(model, source=None), 300.0))
    single = ff.analyze(ff.simulate(ff.BeltOscillator(zeta=0.0, vb=1000.0), ff.Coulomb(0.1, 0.2), ff.Exact(),
                                    t_end=300.0, x0=0.1005, v0=0.0))
    assert single.steady_state.kind == "periodic"
    assert a.steady_state.kind == "periodic" and a.steady_state.period == pytest.approx(2.0 * math.pi, rel=1e-9)
    assert a.amplitude["X_max"]["x"] == pytest.approx(0.1005, rel=1e-9)
    assert a.amplitude["X_min"]["x"] == pytest.approx(0.0995, rel=1e-9)


def test_a_structure_without_contacts_runs_as_its_linear_closed_form():
    """Contacts are optional: two masses on springs and dampers alone.  The run crashed on numpy's "cannot
    reshape array of size 0" (the check of the contacts' directions); it is exp(A t) q0, and settles at rest."""
    model = {"dof": ["x1", "x2"], "mass": [1.0, 2.0],
             "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.5}],
             "damper": [{"on": {"x2": 1.0}, "c": 0.3}], "initial": {"q": {"x1": 0.2}}}
    motion = simulate_system(System.from_dict(model, source=None), 200.0)
    k = np.array([[1.5, -0.5], [-0.5, 0.5]])
    c = np.array([[0.0, 0.0], [0.0, 0.3]])
    m_inv = np.diag([1.0, 0.5])
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-m_inv @ k, -m_inv @ c]])
    times = np.linspace(0.0, 30.0, 61)
    closed = np.stack([expm(a * t) @ np.array([0.2, 0.0, 0.0, 0.0]) for t in times], axis=1)
    np.testing.assert_allclose(motion.states(times), closed, atol=1e-12)
    # every root decays (the slowest at -0.0048, the damper on x2 alone): certified to come to rest, as a
    # structure sliding for good is (the state is still 0.075 at tau = 200)
    assert np.linalg.eigvals(a).real.max() < 0.0
    assert analyze_structure(motion).steady_state.kind == "equilibrium"
