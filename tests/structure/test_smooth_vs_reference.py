"""The adaptive structure solver with smooth laws (Stribeck, cubic) against the independent scipy reference.

Random 2-3 dof structures (``models/``): oblique contacts, full or diagonal
mass matrices, normal loads depending on q, a harmonic force, each contact
with its own law.  The reference (tests/structure/reference.py) integrates
each phase with DOP853 and events, the smooth slip forces s mu(|V_r|) N(q) in
its right-hand side, and decides the modes at every switch itself.  Each
comparison's tolerance is the two integrators' own accuracy: the difference
between a run at rtol 1e-10 and one at 1e-12 bounds the 1e-12 run's error.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from frictionflow.solvers.structure import simulate_system
from frictionflow.system import assemble, load_system

from . import reference as ref

MODELS = Path(__file__).parent / "models"
T_END = 60.0
#: the reference's longest step: solve_ivp finds an event where V_r changes sign between steps, so a dip through
#: V_r = 0 and back within one step would be missed
MAX_STEP = 0.05


def engine_switches(motion) -> tuple[np.ndarray, np.ndarray]:
    """The engine's switch times and the modes entered, a tie (rows at one time, one per contact) taken as one."""
    t = np.asarray(motion.switches, dtype=float)
    modes = np.array(motion.modes[:, 0], dtype=np.int8)
    entered = []
    for c, m in zip(motion.switch_contact, motion.switch_mode):
        modes[c] = m
        entered.append(modes.copy())
    last = np.append(np.diff(t) > 1e-9 * np.maximum(1.0, t[1:]), True)
    return t[last], np.array(entered, dtype=np.int8).reshape(len(t), -1)[last]


@lru_cache(maxsize=None)  # the short slip's runs serve two tests
def runs(name: str):
    """The adaptive solver and the reference, each at rtol 1e-12 and 1e-10."""
    system = load_system(MODELS / f"{name}.toml")
    asm = assemble(system)
    fine, coarse = (simulate_system(system, T_END, solver="adaptive", rtol=r, atol=r * 1e-2) for r in (1e-12, 1e-10))
    ref_fine, ref_coarse = (ref.integrate(asm, T_END, rtol=r, atol=r * 1e-2, max_step=MAX_STEP) for r in (1e-12, 1e-10))
    return fine, coarse, ref_fine, ref_coarse


@pytest.mark.parametrize("name", ["short_slip", "tie", "three_stribeck"])
def test_the_adaptive_solver_switches_as_the_reference(name):
    fine, coarse, ref_fine, ref_coarse = runs(name)
    times, modes = engine_switches(fine)
    assert fine.status == "ok" and ref_fine.status == "ok" and len(times) >= 20
    np.testing.assert_array_equal(modes, ref_fine.switch_modes)
    # each integrator's error, bounded by its own runs' difference
    err = np.abs(engine_switches(coarse)[0] - times).max() + np.abs(ref_coarse.switches - ref_fine.switches).max()
    np.testing.assert_allclose(times, ref_fine.switches, rtol=0, atol=err)
    err_state = (np.abs(coarse.state[:, -1] - fine.state[:, -1]).max()
                 + np.abs(ref_coarse.state[:, -1] - ref_fine.state[:, -1]).max())
    np.testing.assert_allclose(fine.state[:, -1], ref_fine.state[:, -1], rtol=0, atol=err_state)


def test_the_cases_do_what_they_are_here_for():
    """A slip of 3.5e-3 that starts at a tie (solve_ivp, stepping from V_r = 0, took its return for an event at its
    start, or missed it); a stick that releases the other contact at its instant; smooth laws of every kind."""
    short = engine_switches(runs("short_slip")[0])
    gaps = np.diff(short[0])
    i = int(np.argmin(gaps))
    assert gaps[i] < 5e-3 and np.sum(short[1][i] != short[1][i - 1]) == 2  # a tie starts the short slip
    tie = simulate_system(load_system(MODELS / "tie.toml"), T_END, solver="adaptive")
    same = np.flatnonzero(np.diff(np.asarray(tie.switches)) == 0.0)
    assert any(tie.switch_mode[i] != 0 and tie.switch_mode[i + 1] == 0 for i in same)
    laws = {str(c.law.name) for n in ("short_slip", "tie", "three_stribeck")
            for c in load_system(MODELS / f"{n}.toml").contacts}
    assert laws == {"stribeck", "cubic"}


@pytest.mark.parametrize("rtol, max_step", [(1e-10, np.inf), (1e-13, MAX_STEP)])
def test_the_reference_switches_alike_at_any_tolerance_and_step(rtol, max_step):
    """The reference's own consistency on the short slip: before, it looped at rtol 1e-11 and missed the slip's end
    at 1e-12."""
    asm = assemble(load_system(MODELS / "short_slip.toml"))
    base = ref.integrate(asm, T_END, rtol=1e-12, atol=1e-14, max_step=MAX_STEP)
    other = ref.integrate(asm, T_END, rtol=rtol, atol=rtol * 1e-2, max_step=max_step)
    np.testing.assert_array_equal(other.switch_modes, base.switch_modes)
    np.testing.assert_allclose(other.switches, base.switches, rtol=0, atol=1e-7)


def test_a_slip_that_ends_within_the_adaptive_solver_s_step_ends_where_the_reference_says():
    """A contact leaving V_r = 0 and back within one step of the adaptive solver (a slip of 4.96e-3, V_r dipping
    2.5e-6, its start second order: mu(0) = F_s): the stick was taken at the step's end, 0.04 late at rtol 1e-8
    and 7e-4 at 1e-12; it is now located inside the step."""
    system = load_system(MODELS / "return_within_a_step.toml")
    reference = ref.integrate(assemble(system), 40.0, rtol=1e-12, atol=1e-14, max_step=MAX_STEP)
    for rtol in (1e-8, 1e-10):  # measured 3.1e-8 and 6.4e-10 off the reference
        times, modes = engine_switches(simulate_system(system, 40.0, solver="adaptive", rtol=rtol, atol=rtol * 1e-2))
        np.testing.assert_array_equal(modes, reference.switch_modes)
        np.testing.assert_allclose(times, reference.switches, rtol=0, atol=10 * rtol)
        slips = np.diff(times)[(modes[:-1, 1] != 0) & (modes[1:, 1] == 0)]  # contact 1's slips that end in a stick
        assert slips.min() < 5e-3
