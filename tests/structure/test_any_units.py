"""Runs of structures do not depend on the model's units.

The adaptive solver's absolute tolerance was one number (1e-13) over positions, velocities and
works in the model's own units: the Stribeck chain with lengths in units a
billion times longer (a nanometre motion in metres) had an energy residual of
3e-5 instead of 4e-12 and its last switch 1.6e-3 late, as the error test
admitted errors of a thousandth of the motion.  Now each group's tolerance is
the solver's atol in the structure's own sizes
(:func:`frictionflow.system.assemble.state_scales`), and a step too short to
take is measured against the structure's time, not one unit of it.  A
model's initial state takes the range of its other numbers, and the exact
engine judges a mode basis's condition in the structure's own time.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from frictionflow.friction import law_classes
from frictionflow.orbits import find_structure_orbit
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import System, assemble
from frictionflow.system.assemble import state_scales

from .test_structure_kinds import _in_time_units

MODELS = Path(__file__).parents[2] / "examples" / "models"
#: a law parameter's name -> its dimension
LAW_DIMENSION = {p.name: p.dimension for cls in law_classes() for p in getattr(cls, "parameters", ())}
#: the dimensions that scale with the unit of length when forces are measured in the same factor (stiffness and
#: damping, force over length and over velocity, then keep their numbers; so do masses)
WITH_LENGTH = {"force", "velocity", "length"}


def _in_length_units(system: System, f: float) -> System:
    """``system`` with lengths and forces both measured in units ``f`` times smaller: positions, velocities, belts,
    friction levels and force amplitudes times f (masses, stiffnesses and dampers unchanged): q(t) becomes f q(t)."""
    def scaled(entry: str) -> bool:
        kind, *_, last = entry.split(".")
        return (entry.startswith("initial.") or (kind == "contact" and (last == "belt" or LAW_DIMENSION.get(last) in WITH_LENGTH))
                or (kind == "force" and last == "amplitude"))

    return system.with_entries({e: system.entry(e) * f for e in system.entries() if scaled(e)})


def _stribeck_chain() -> System:
    return System.from_dict(tomllib.loads((MODELS / "stribeck_chain.toml").read_text()), source=None)


@pytest.mark.parametrize("length, time", [(1e-9, 1.0), (1e-12, 1.0), (1e6, 1.0), (1.0, 1e-6), (1e-9, 1e-9)])
def test_the_stribeck_chain_runs_alike_in_any_units(length, time):
    """The same motion in other units: every switch (its time over the unit of time) and the end state (over its
    units) equal to the unit run's to 1e-9, and the energy balance closed as well as there (a residual of 3e-5
    in nanometre units before)."""
    unit_system = _stribeck_chain()
    unit = simulate_system(unit_system, 300.0, solver="adaptive")
    other = simulate_system(_in_time_units(_in_length_units(unit_system, length), time), 300.0 * time, solver="adaptive")
    assert len(other.switches) == len(unit.switches) > 100
    np.testing.assert_allclose(other.switches / time, unit.switches, rtol=0, atol=1e-9)
    n = len(unit.dof)
    np.testing.assert_allclose(other.state[:n, -1] / length, unit.state[:n, -1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(other.state[n:, -1] * time / length, unit.state[n:, -1], rtol=0, atol=1e-9)
    assert unit.energy_residual < 1e-10 and other.energy_residual < 1e-10


def test_the_sizes_scale_as_their_quantities():
    """state_scales in other units of length and time: time by s, positions by f, velocities by f / s, works by
    f^2 (forces and lengths both by f), each from the same elements."""
    unit_system = _stribeck_chain()
    base = np.array(state_scales(assemble(unit_system), 300.0))
    f, s = 1e-7, 1e3
    other = np.array(state_scales(assemble(_in_time_units(_in_length_units(unit_system, f), s)), 300.0 * s))
    np.testing.assert_allclose(other / base, [s, f, f / s, f * f], rtol=1e-12)
    assert np.all(base > 0.0)


@pytest.mark.parametrize("s", [1e-9, 1e-12, 1e-15])
def test_a_chain_in_tiny_units_of_time_starts_on_its_belt_and_runs_alike(s):
    """The stick-slip chain in nanoseconds and shorter: its masses start riding belts at 5e7 units a unit of time
    and more, which the initial state's range (the single mass's 1e6) refused while the belts were taken.  In
    picoseconds the exact engine then refused every mode combination as defective ("spring.0's rate 1e+12 beside
    its slowest rate 8.17e+11 spans more than ..."): the basis's condition was judged with velocity rows 1e12
    times the position rows.  Now the same switches over the unit of time as in seconds."""
    unit_system = System.from_dict(tomllib.loads((MODELS / "stick_slip_chain.toml").read_text()), source=None)
    tiny = _in_time_units(unit_system, s)
    assert tiny.entry("initial.v.x1") == pytest.approx(0.05 / s, rel=1e-12)
    unit, other = simulate_system(unit_system, 300.0), simulate_system(tiny, 300.0 * s)
    assert len(other.switches) == len(unit.switches) > 100
    np.testing.assert_allclose(other.switches / s, unit.switches, rtol=0, atol=1e-9)


@pytest.mark.parametrize("length, time", [(1.0, 1e-12), (1e-9, 1e-15), (1e-12, 1.0)])
def test_the_chain_s_orbit_is_the_same_in_any_units(length, time):
    """Shooting the stick-slip chain's cycle in picoseconds stalled at a residual of 1.9e-9 of the orbit's size
    (the section's crossing was located to 1e-15 time units, a ten-thousandth of the period there); with that
    mended the trivial multiplier came out 1.00005 (the phase matrices' unit steps moved the positions by 1e-12
    of their size).  Now the same period (over the unit of time), stick fractions and multipliers in any units."""
    unit_system = System.from_dict(tomllib.loads((MODELS / "stick_slip_chain.toml").read_text()), source=None)
    unit = find_structure_orbit(unit_system, t_transient=1500.0)
    other = find_structure_orbit(_in_time_units(_in_length_units(unit_system, length), time), t_transient=1500.0 * time)
    assert other.period / time == pytest.approx(unit.period, rel=1e-12)
    np.testing.assert_allclose(other.stick_fraction, unit.stick_fraction, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.sort(np.abs(other.multipliers)), np.sort(np.abs(unit.multipliers)), rtol=0, atol=1e-9)
    assert np.max(np.abs(other.multipliers)) == pytest.approx(1.0, abs=1e-9)  # the autonomous cycle's own


@pytest.mark.parametrize("s", [1e-9, 3e-12, 1e-12])
def test_the_orbit_s_nontrivial_multiplier_is_its_multiplier_in_any_units(s):
    """The nontrivial multipliers are M's eigenvalues across the tangent f (B^T M B).  In short units of time M's
    position and velocity blocks part by 1/s^2 and the product, taken in the model's units, rounded: in units
    3e-12 the stability-deciding multiplier came out -0.727429 while M's own eigenvalues (balanced by LAPACK)
    held -0.727532 (found by hand: orbit --json's "multiplier" beside its "multipliers"); 8.5e-11 off in
    nanoseconds.  Now both agree with the run in seconds to 1e-12."""
    unit_system = System.from_dict(tomllib.loads((MODELS / "stick_slip_chain.toml").read_text()), source=None)
    unit = find_structure_orbit(unit_system, t_transient=1500.0)
    other = find_structure_orbit(_in_time_units(unit_system, s), t_transient=1500.0 * s)
    for orbit in (unit, other):
        listed = [m for m in orbit.multipliers if abs(m - 1.0) > 1e-6]
        assert abs(orbit.multiplier - listed[0]) < 1e-12
    assert abs(other.multiplier - unit.multiplier) < 1e-12
    assert -0.73 < unit.multiplier.real < -0.72
