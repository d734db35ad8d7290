"""Issue 22's exact engine against the independent reference integrator (tests/structure/reference.py).

Two-mass chains with Coulomb contacts, phases where one mass sticks while
the other slips, a stick limit per the spring rule, a normal load depending
on q, a harmonic force and a full mass matrix; and a contact loss.  The
tolerance of each comparison is the reference's own accuracy, measured here:
the largest difference between the reference at rtol 1e-10 and at rtol 1e-12
(an 8th-order method's error falls about a hundredfold between the two, so
this difference bounds the 1e-12 run's error with a wide margin; the engine
is exact up to rounding and root finding).
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import Coulomb
from frictionflow.solvers.structure import run_assembly

from . import reference as ref
from .chains import Elements, build, chain

T_END = 100.0
DT = 0.05


def one_sticks_other_slips():
    """Unit masses, springs to ground and between, a damper each, one belt each (both at 0.1)."""
    return chain(2, [0.1, 0.1], [Coulomb(0.3, 0.4), Coulomb(0.2, 0.35)], q0=[0.0, 0.5])


def mixed(normal_x2: float = 0.2) -> Elements:
    """Belts in opposite directions, the spring rule on contact 0 with N_0 = 1 + ``normal_x2`` x2, a force on x2."""
    springs = ([[1.0, 0.0], [1.0, -1.0], [0.0, 1.0]], [1.0, 0.6, 0.7])
    dampers = ([[1.0, 0.0], [1.0, -1.0]], [0.05, 0.02])
    laws = [Coulomb(0.3, 0.45, stick_force="spring"), Coulomb(0.25, 0.3)]
    contacts = ([[1.0, 0.0], [0.0, 1.0]], [0.2, -0.1], laws, [[1.0, 0.0, normal_x2], [1.0, 0.0, 0.0]])
    return Elements([[1.0, 0.1], [0.1, 1.5]], springs, dampers, contacts, ([[0.0, 1.0]], [0.2], [0.8], [0.4]),
                    [0.3, -0.4], [0.0, 0.0])


CASES = {"one sticks, the other slips": one_sticks_other_slips, "spring rule, normal load, forced": lambda: build(mixed())}


def references(asm, times: np.ndarray, t_end: float):
    """The reference at rtol 1e-12 and 1e-10 on ``times`` (unique, ascending)."""
    fine = ref.integrate(asm, t_end, t_eval=times, rtol=1e-12, atol=1e-14, work=True)
    coarse = ref.integrate(asm, t_end, t_eval=times, rtol=1e-10, atol=1e-12, work=True)
    assert len(coarse.switches) == len(fine.switches)
    np.testing.assert_array_equal(coarse.switch_modes, fine.switch_modes)
    return fine, coarse


def spread(a: np.ndarray, b: np.ndarray) -> float:
    """Largest difference of two arrays (0 for empty ones)."""
    return float(np.max(np.abs(a - b))) if np.size(a) else 0.0


def status_text(motion) -> str:
    """The run's status as text ("ok", or naming "contact_lost")."""
    return motion.status if isinstance(motion.status, str) else str(motion.status)


def switch_times(motion) -> np.ndarray:
    """The engine's switch times (a mapping of event records gives its "t")."""
    sw = motion.switches
    return np.asarray(sw["t"] if isinstance(sw, dict) else sw, dtype=float)


@pytest.mark.parametrize("case", list(CASES))
def test_chain_against_reference(case):
    asm = CASES[case]()
    motion = run_assembly(asm, T_END, dense_dt=DT)
    assert "contact_lost" not in status_text(motion)
    times, inverse = np.unique(motion.t, return_inverse=True)
    fine, coarse = references(asm, times, T_END)
    stuck_one = {(0, 1), (1, 0), (0, -1), (-1, 0)} & set(map(tuple, fine.modes.T.tolist()))
    assert stuck_one and len(fine.switches) > 10  # the case does what it is here for
    tol_switch = spread(coarse.switches, fine.switches)
    switches = switch_times(motion)
    assert len(switches) == len(fine.switches)
    np.testing.assert_allclose(switches, fine.switches, rtol=0, atol=tol_switch)
    state = fine.state[:, inverse]
    np.testing.assert_allclose(motion.state, state, rtol=0, atol=spread(coarse.state, fine.state))
    # modes and forces at the samples off the switches (a sample on a switch belongs to either side)
    away = np.min(np.abs(motion.t[:, None] - fine.switches[None, :]), axis=1) > 10.0 * tol_switch + 1e-12
    np.testing.assert_array_equal(motion.modes[:, away], fine.modes[:, inverse][:, away])
    force_tol = spread(coarse.force[:, inverse][:, away], fine.force[:, inverse][:, away])
    np.testing.assert_allclose(motion.force[:, away], fine.force[:, inverse][:, away], rtol=0, atol=force_tol)
    # between the samples (motion.at), at times no run sampled
    off = np.linspace(0.013, T_END - 0.013, 137)
    fine_off = ref.integrate(asm, T_END, t_eval=off, rtol=1e-12, atol=1e-14)
    coarse_off = ref.integrate(asm, T_END, t_eval=off, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(np.array([motion.at(t) for t in off]).T, fine_off.state, rtol=0,
                               atol=spread(coarse_off.state, fine_off.state))
    # the work per element, by channel name
    works = dict(zip(motion.channels, motion.work))
    assert set(works) == set(fine.channels)
    for i, name in enumerate(fine.channels):
        np.testing.assert_allclose(works[name], fine.work[i, inverse], rtol=0,
                                   atol=spread(coarse.work[i], fine.work[i]), err_msg=name)


def test_contact_loss_against_reference():
    """N_0 = 1 - 3.5 x2 reaches 0 after a few switches: the engine stops there, as the reference does."""
    asm = build(mixed(-3.5))
    motion = run_assembly(asm, T_END, dense_dt=DT)
    fine = ref.integrate(asm, T_END, dense_dt=DT, rtol=1e-12, atol=1e-14)
    coarse = ref.integrate(asm, T_END, dense_dt=DT, rtol=1e-10, atol=1e-12)
    assert fine.status == coarse.status == "contact_lost" and fine.lost[0] == 0 and len(fine.switches) >= 3
    tol = abs(coarse.lost[1] - fine.lost[1])
    assert "contact_lost" in status_text(motion)
    assert abs(motion.t[-1] - fine.lost[1]) <= tol  # the run ends on the loss
    switches = switch_times(motion)
    np.testing.assert_allclose(switches, fine.switches, rtol=0, atol=spread(coarse.switches, fine.switches))
