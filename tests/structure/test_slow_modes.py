"""A run shorter than the structure's slowest time scale is not called chaotic or quasi-periodic.

Two masses in a chain (examples/models/two_mass_chain.toml's numbers) with
either the first mass 1e8 times heavier (a swing of period ~5e4) or a damper
of 1e6 on it (a creep of rate ~k / c): over 300 time units the first drifted
linearly and gave a finite-time exponent of 1.4e-3 above its uncertainty
(``chaotic``), the second crept by 1e-7 a period and revisited its section
without closing in (``quasi_periodic``).  Neither tells anything about the
motion beyond its window: both are ``not_settled``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from frictionflow.analysis.structure import analyze_structure, slowest_period
from frictionflow.analysis.stability import steady_sliding
from frictionflow.solvers.structure import run_assembly, simulate_system
from frictionflow.system import System, assemble

SPRINGS = [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.5}, {"on": {"x2": 1.0}, "k": 1.0}]
CHAIN = {"dof": ["x1", "x2"], "mass": [1.0, 1.0], "spring": SPRINGS,
         "damper": [{"on": {"x1": 1.0}, "c": 0.04}, {"on": {"x2": 1.0}, "c": 0.04}],
         "contact": [{"on": {x: 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.1, "fs": fs}
                     for x, fs in (("x1", 0.15), ("x2", 0.2))],
         "initial": {"q": {"x2": 0.2}}}


def chain(mass1: float = 1.0, c1: float = 0.04, springs=SPRINGS) -> System:
    """The chain with the first mass ``mass1`` and its damper ``c1``."""
    return System.from_dict({**CHAIN, "mass": [mass1, 1.0], "spring": springs,
                             "damper": [{"on": {"x1": 1.0}, "c": c1}, {"on": {"x2": 1.0}, "c": 0.04}]})


def pencil_period(system: System) -> float:
    """2 pi / the least nonzero |lambda| of det(lambda^2 M + lambda C + K) = 0: scipy's generalized eigenvalues of
    the pencil ([0 I; -K -C], [I 0; 0 M]), zeros those below 1e-9."""
    a = assemble(system)
    n = len(a.mass)
    eye, zero = np.eye(n), np.zeros((n, n))
    lam = scipy.linalg.eigvals(np.block([[zero, eye], [-a.stiffness, -a.damping]]),
                               np.block([[eye, zero], [zero, a.mass]]))
    rates = np.abs(lam[np.abs(lam) > 1e-9])
    return 2.0 * math.pi / rates.min()


@pytest.mark.parametrize("system", [chain(), chain(mass1=1e8), chain(c1=1e4), chain(springs=SPRINGS[1:2])],
                         ids=["chain", "heavy", "stiff damper", "free: one spring between the masses"])
def test_the_slowest_period_is_the_pencils(system):
    assert slowest_period(assemble(system)) == pytest.approx(pencil_period(system), rel=1e-6)


def test_a_single_mass_s_slowest_period_is_its_characteristic_root_s():
    system = System.from_dict({"dof": ["x"], "mass": [2.0], "spring": [{"on": {"x": 1.0}, "k": 5.0}],
                               "damper": [{"on": {"x": 1.0}, "c": 30.0}]})
    slow = np.abs(np.roots([2.0, 30.0, 5.0])).min()  # overdamped: the creep's root
    assert slowest_period(assemble(system)) == pytest.approx(2.0 * math.pi / slow, rel=1e-12)


@pytest.mark.parametrize("system", [chain(mass1=1e8), chain(c1=1e6)], ids=["heavy", "stiff damper"])
def test_a_run_shorter_than_the_slowest_mode_is_not_settled(system):
    assert slowest_period(assemble(system)) > 1e4
    ss = analyze_structure(simulate_system(system, 300.0)).steady_state
    assert ss.kind == "not_settled" and not math.isfinite(ss.lyapunov)



def _sliding_pair(c: float) -> System:
    """Two masses sliding steadily (fs above the springs' pull), a damper ``c`` between them."""
    contacts = [{"on": {x: 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.1, "fs": fs}
                for x, fs in (("x1", 0.2), ("x2", 0.25))]
    dampers = [{"on": {"x1": 1.0}, "c": 0.02}, {"on": {"x2": 1.0}, "c": 0.02}, {"on": {"x1": 1.0, "x2": -1.0}, "c": c}]
    return System.from_dict({**CHAIN, "damper": dampers, "contact": contacts})


@pytest.mark.parametrize("c", [1e4, 1e6])
def test_steady_sliding_behind_a_stiff_damper_is_proven(c):
    """A damper of c between two sliding masses leaves a slow mode of rate about 1 / c: its real part is far
    below 1e-8 of the spectrum's size (2c), the old floor of rounding, though known to far better than that, so
    the proof that the run slides on for ever failed and the run was not settled however long it ran.  Now the
    run to 300 is an equilibrium, and the proof's claim holds: run on to 20 slow time constants, no switch comes
    and the state has closed in on the steady-sliding equilibrium (its distance shrunk by e^-20)."""
    system = _sliding_pair(c)
    assert analyze_structure(simulate_system(system, 300.0)).steady_state.kind == "equilibrium"
    slow = 2.0 * math.pi / slowest_period(assemble(system))
    assert slow < 1e-8 * 2.0 * c  # what the old floor could not tell from 0
    far = run_assembly(assemble(system), 20.0 / slow)  # (the start, the end and any switch)
    assert len(far.switches) == 0
    rest = steady_sliding(assemble(system)).q
    start = np.abs(far.state[:2, 0] - rest).max()
    assert np.abs(far.state[:2, -1] - rest).max() < 1e-6 * start
