"""A slowly attracting stick-slip cycle is not a torus.

A 3-block Burridge-Knopoff chain (Coulomb contacts) settles on a stable cycle
whose nontrivial multipliers are a complex pair of modulus 0.9989 a period:
the section spirals in at about 1.8e-4 a time unit, inside the Lyapunov
exponent's uncertainty, and its points revisit the first half's to 5 % of the
motion's size.  It was reported ``quasi_periodic`` (and at t_end 6000 with a
positive exponent).  The section's quarters now must not close in on a point.
"""

from __future__ import annotations

import numpy as np

from frictionflow.analysis.structure import analyze_structure
from frictionflow.analysis.structure_lyapunov import closing_in
from frictionflow.orbits import find_structure_orbit
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import System

SPRINGS = [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x2": 1.0}, "k": 1.0}, {"on": {"x3": 1.0}, "k": 1.0},
           {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.5}, {"on": {"x2": 1.0, "x3": -1.0}, "k": 0.5}]
CHAIN = {"dof": ["x1", "x2", "x3"], "mass": [1.0, 1.0, 1.0], "spring": SPRINGS,
         "damper": [{"on": {x: 1.0}, "c": 0.05} for x in ("x1", "x2", "x3")],
         "contact": [{"on": {x: 1.0}, "belt": 0.05, "friction": "coulomb", "fd": fd, "fs": fd + 0.1}
                     for x, fd in (("x1", 0.1), ("x2", 0.11), ("x3", 0.12))],
         "initial": {"q": {"x1": 0.01, "x2": 0.02, "x3": 0.03}}}


def test_a_slowly_attracting_cycle_is_not_settled_rather_than_quasi_periodic():
    system = System.from_dict(CHAIN)
    orbit = find_structure_orbit(system, t_transient=3000.0)
    mu = np.sort(np.abs(orbit.multipliers))[::-1]
    assert orbit.stable and 0.99 < mu[1] < 0.9995  # the trivial 1 first, then the slow pair: it attracts, slowly
    for t_end in (3000.0, 6000.0):
        assert analyze_structure(simulate_system(system, t_end)).steady_state.kind == "not_settled"


def test_contracting_tells_a_spiral_from_a_closed_curve():
    k = np.arange(400)
    angle = 2.0 * np.pi * k * (np.sqrt(5.0) - 1.0) / 2.0  # an irrational rotation: a curve filled evenly
    curve = np.vstack([np.cos(angle), 0.5 * np.sin(angle)])
    assert not closing_in(curve)
    assert closing_in(curve * np.exp(-1e-3 * k))  # 0.67 of its size over the run
    assert not closing_in(curve * np.exp(-1e-5 * k))  # 0.996: within the torus's own spread
